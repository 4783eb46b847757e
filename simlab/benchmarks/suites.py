"""The benchmark suites: each runs over env counts and returns one row (a dict) per measurement."""

from __future__ import annotations

import os
import traceback

from .physics import bench_physics


def _guarded(rows: list[dict], label: dict, fn) -> None:
    """Run one measurement; a failure (out of memory, say) becomes a row that says so."""
    try:
        rows.append(fn())
    except Exception as err:  # noqa: BLE001 - report and go on with the other sizes
        traceback.print_exc()
        rows.append({**label, "error": f"{type(err).__name__}: {err}"})
        print(f"  {label}: failed: {type(err).__name__}: {err}")


def physics(device: str, num_envs: list[int], steps: int, robots: list[str], **_) -> list[dict]:
    rows: list[dict] = []
    for robot in robots:
        for n in num_envs:
            _guarded(
                rows,
                {"robot": robot, "device": device, "num_envs": n},
                lambda robot=robot, n=n: bench_physics(robot, n, device, steps),
            )
    return rows


def env_step(device: str, num_envs: list[int], steps: int, tasks: list[str] | None, **kw) -> list[dict]:
    return _env_rows(device, num_envs, steps, tasks, False, kw.get("graphs", [True]), _env_overrides(kw))


def env_step_with_policy(device: str, num_envs: list[int], steps: int, tasks: list[str] | None, **kw) -> list[dict]:
    return _env_rows(device, num_envs, steps, tasks, True, kw.get("graphs", [True]), _env_overrides(kw))


def _env_overrides(kw: dict) -> list[str]:
    """The ``env.*`` ones of ``--overrides``: the env suites build each task with them."""
    from simlab.tasks.utils.hydra import env_overrides_in

    return env_overrides_in(getattr(kw.get("solve_args"), "overrides", None) or [])


def _env_rows(device, num_envs, steps, tasks, with_policy: bool, graphs: list[bool], overrides=()) -> list[dict]:
    from .env_suites import DEFAULT_TASKS, bench_env

    rows: list[dict] = []
    for task in tasks or DEFAULT_TASKS:
        for n in num_envs:
            for graph in graphs:
                _guarded(
                    rows,
                    {"task": task, "device": device, "num_envs": n},
                    lambda task=task, n=n, graph=graph: bench_env(
                        task, n, device, steps, with_policy, graph, overrides
                    ),
                )
    return rows


def train(device: str, num_envs: list[int], tasks: list[str] | None, iterations: int, **kw) -> list[dict]:
    from .env_suites import bench_train

    rows: list[dict] = []
    for task in tasks or ["simlab/Cartpole-v0", "simlab/Humanoid-Direct-v0"]:
        for n in num_envs:
            for graph in kw.get("graphs", [True]):
                _guarded(
                    rows,
                    {"task": task, "device": device, "num_envs": n},
                    lambda task=task, n=n, graph=graph: bench_train(
                        task, n, device, iterations, graph, kw.get("fast_update")
                    ),
                )
    return rows


# `simlab bench` flags of the solve suite, named as time_to_policy's parameters
SOLVE_FLAGS = (
    "library",
    "max_iterations",
    "eval_every",
    "seed",
    "eval_envs",
    "eval_seconds",
    "reward_threshold",
    "log_root",
    "resume",
)


def solve(
    device: str,
    num_envs: list[int | None],
    tasks: list[str] | None,
    solve_args,
    fast_update=None,
    **_,
) -> list[dict]:
    """Time to a solved task: one row per task and env count (``None``: the task's own).

    Its start-up share counts from the process start, so one measurement runs here and more than
    one run each in a fresh process. ``--processes N`` runs each N times, one fresh process after
    the other, so that the later ones start with the caches the first filled (Python's bytecode
    with ``--pycache_prefix``, Warp's kernels in ``--warp_cache`` or Warp's own cache folder).
    """
    from .solve import time_to_policy

    a = solve_args
    runs = [(task, n) for task in tasks or ["simlab/Cartpole-v0"] for n in num_envs]
    if a.processes:
        rows = []
        for task, n in runs:
            for process in range(1, a.processes + 1):
                print(f"\n[solve] {task}: fresh process {process} of {a.processes}", flush=True)
                rows.append({"process": process, **_solve_in_child(task, n, device, a)})
        return rows
    if len(runs) > 1:
        return [_solve_in_child(task, n, device, a) for task, n in runs]
    (task, n), rows = runs[0], []
    _guarded(
        rows,
        {"task": task, "device": device, "num_envs": n},
        lambda: time_to_policy(
            task,
            device=device,
            num_envs=n,
            overrides=[*a.overrides, *_fast_path_overrides(fast_update)],
            allow_module=a.allow_module,
            **{flag: getattr(a, flag) for flag in SOLVE_FLAGS},
        ),
    )
    return rows


def _fast_path_overrides(fast_update: bool | None) -> list[str]:
    """``--ppo_update``: rsl_rl's own update and act (False), or simlab's fast update and act graph (True)."""
    if fast_update is None:
        return []
    return (
        ["agent.fast_update=true", "agent.graph_act=null"]
        if fast_update
        else ["agent.fast_update=false", "agent.graph_act=false"]
    )


def _solve_in_child(task: str, num_envs: int | None, device: str, a) -> dict:
    import json
    import subprocess
    import sys
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "solve.json")
        argv = [sys.executable, "-m", "simlab", "bench", "solve", "--tasks", task, "--device", device, "--json", out]
        for flag in SOLVE_FLAGS:
            if getattr(a, flag) is not None:
                argv += [f"--{flag}", str(getattr(a, flag))]
        if num_envs is not None:
            argv += ["--num_envs", str(num_envs)]
        argv += ["--ppo_update", a.ppo_update]
        if a.overrides:
            argv += ["--overrides", *a.overrides]
        for module in a.allow_module:
            argv += ["--allow_module", module]
        proc = subprocess.run(argv, env=_child_environment(a))
        if proc.returncode != 0 or not os.path.isfile(out):
            return {"task": task, "device": device, "num_envs": num_envs, "error": f"exit code {proc.returncode}"}
        with open(out) as f:
            return json.load(f)["results"]["solve"][0]


def _child_environment(a) -> dict[str, str]:
    """The environment of a fresh solve process: ``--pycache_prefix`` keeps every module's bytecode
    in that folder (what an installed package has next to its sources), ``--warp_cache`` is Warp's
    kernel cache (``WARP_CACHE_PATH``)."""
    env = dict(os.environ)
    if getattr(a, "pycache_prefix", None):
        env["PYTHONPYCACHEPREFIX"] = os.path.abspath(a.pycache_prefix)
        env.pop("PYTHONDONTWRITEBYTECODE", None)
    if getattr(a, "warp_cache", None):
        env["WARP_CACHE_PATH"] = os.path.abspath(a.warp_cache)
    return env
