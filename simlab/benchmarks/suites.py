"""The benchmark suites: each runs over env counts and returns one row (a dict) per measurement."""

from __future__ import annotations

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
    return _env_rows(device, num_envs, steps, tasks, False, kw.get("graphs", [True]))


def env_step_with_policy(device: str, num_envs: list[int], steps: int, tasks: list[str] | None, **kw) -> list[dict]:
    return _env_rows(device, num_envs, steps, tasks, True, kw.get("graphs", [True]))


def _env_rows(device, num_envs, steps, tasks, with_policy: bool, graphs: list[bool]) -> list[dict]:
    from .env_suites import DEFAULT_TASKS, bench_env

    rows: list[dict] = []
    for task in tasks or DEFAULT_TASKS:
        for n in num_envs:
            for graph in graphs:
                _guarded(
                    rows,
                    {"task": task, "device": device, "num_envs": n},
                    lambda task=task, n=n, graph=graph: bench_env(task, n, device, steps, with_policy, graph),
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
                    lambda task=task, n=n, graph=graph: bench_train(task, n, device, iterations, graph),
                )
    return rows
