"""``simlab bench``: measure and print throughput tables; optionally write them as JSON.

    simlab bench physics --robots cartpole --num_envs 1024 4096 --device cpu
    simlab bench --device cuda:0 --json bench.json       # every suite but solve
    simlab bench solve --tasks simlab/Cartpole-v0 --device cpu   # time to a policy that solves the task

The costs of single parts, each with its own flags (``simlab bench <tool> --help``):

    simlab bench ops step --task simlab/Velocity-Flat-Unitree-Go2-v0  # torch ops, Warp launches per step, by part
    simlab bench ops update --task simlab/Cartpole-v0 --device cpu      # torch ops of a PPO update and rollout step
    simlab bench ops sync --device cuda:0 --num_envs 4096               # the rollout's host read: per step or iteration
    simlab bench startup --device cpu --runs 5                          # process start to the first iteration
    simlab bench viewer --device cpu --tasks simlab/Cartpole-v0         # training time with the web viewer open
    simlab bench video --task simlab/Cartpole-v0 --device cpu           # env steps while recording a video
    simlab bench terrain                                                # a step on plane, boxes and height fields
    simlab bench raycast --num_envs 64                                  # one height scan against a physics step
    simlab bench postconstraint --device cuda:0 --num_envs 8192         # the Shadow hand's joint forces: pass on or not

Figures are measured on the machine at hand. Ratios compare variants measured in alternating
rounds within the same run, which is what holds up on a noisy machine.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
from collections.abc import Callable

SUITES = ("physics", "env", "inference", "train", "solve")
DEFAULT_SUITES = ("physics", "env", "inference", "train")  # solve trains to the end: asked for by name
ROBOTS = ("cartpole", "ant", "humanoid")  # the physics suite's robots (benchmarks/physics.py builds them)


def _print_table(rows: list[dict], columns: list[tuple[str, str, str]]) -> None:
    header = [title for title, _, _ in columns]
    body = []
    for row in rows:
        cells = []
        for _, key, fmt in columns:
            value = row.get(key)
            cells.append("-" if value is None else format(value, fmt) if fmt else str(value))
        body.append(cells)
    widths = [max(len(h), *(len(r[i]) for r in body)) if body else len(h) for i, h in enumerate(header)]
    print("  ".join(h.rjust(w) for h, w in zip(header, widths)))
    for cells in body:
        print("  ".join(c.rjust(w) for c, w in zip(cells, widths)))


PHYSICS_COLUMNS = [
    ("robot", "robot", ""),
    ("device", "device", ""),
    ("envs", "num_envs", "d"),
    ("raw steps/s", "raw_steps_per_s", ",.0f"),
    ("scene steps/s", "scene_steps_per_s", ",.0f"),
    ("raw ms", "raw_ms_per_step", ".3f"),
    ("scene ms", "scene_ms_per_step", ".3f"),
    ("scene/raw", "ratio", ".2f"),
    ("GPU MB", "gpu_memory_mb", ".0f"),
]
ENV_COLUMNS = [
    ("task", "task", ""),
    ("device", "device", ""),
    ("envs", "num_envs", "d"),
    ("env steps/s", "env_steps_per_s", ",.0f"),
    ("physics steps/s", "physics_steps_per_s", ",.0f"),
    ("env ms", "env_ms_per_step", ".3f"),
    ("raw physics steps/s", "raw_physics_steps_per_s", ",.0f"),
    ("env/raw", "ratio", ".2f"),
    ("physics ms", "physics_ms_per_env_step", ".3f"),
    ("outside physics", "outside_physics_share", ".0%"),
    ("outside ms", "outside_ms_per_step", ".3f"),
    ("outside (timed)", "outside_physics_share_timed", ".0%"),
    ("render ms", "render_ms", ".3f"),
    ("renders/step", "renders_per_step", "d"),
    ("render share", "render_share", ".0%"),
    ("graph", "cuda_graph", ""),
    ("GPU MB", "gpu_memory_mb", ".0f"),
    ("Warp MB", "warp_memory_mb", ".0f"),
]
TRAIN_COLUMNS = [
    ("task", "task", ""),
    ("device", "device", ""),
    ("envs", "num_envs", "d"),
    ("env steps/s", "env_steps_per_s", ",.0f"),
    ("s/iteration", "seconds_per_iteration", ".3f"),
    ("iterations", "iterations", "d"),
    ("GPU MB", "gpu_memory_mb", ".0f"),
    ("Warp MB", "warp_memory_mb", ".0f"),
    ("PPO update", "ppo_update", ""),
    ("rollout policy", "rollout_policy", ""),
]
SOLVE_COLUMNS = [
    ("task", "task", ""),
    ("device", "device", ""),
    ("envs", "num_envs", "d"),
    ("seed", "seed", "d"),
    ("solved", "solved", ""),
    ("iteration", "iteration", "d"),
    ("score", "score", ".3f"),
    ("time to policy s", "time_to_policy_s", ".1f"),
    ("start-up s", "startup_s", ".1f"),
    ("rollout s", "rollout_s", ".1f"),
    ("update s", "update_s", ".1f"),
    ("evaluation s", "evaluation_s", ".1f"),
    ("other s", "other_s", ".1f"),
    ("wall s", "wall_s", ".1f"),
    ("process", "process", "d"),
    ("py compiled", "python_modules_compiled", "d"),
    ("Warp compiled", "warp_kernel_modules_compiled", "d"),
]


def _print_solve_breakdown(rows: list[dict]) -> None:
    """Each solve's time as shares, and its start-up as phases: seconds spent reaching each of
    ``simlab train``'s milestones from the one before (the first from the process start)."""
    measured = [r for r in rows if "startup_s" in r]
    if not measured:
        return
    print("\nshares of each run (process start to the end of its last evaluation):")
    shares = [("start-up", "startup_s"), ("rollout", "rollout_s"), ("update", "update_s")]
    shares += [("evaluation", "evaluation_s"), ("other", "other_s")]
    for r in measured:
        total = sum(r[key] for _, key in shares)
        label = f"{r['task']} seed {r['seed']}" + (f" process {r['process']}" if "process" in r else "")
        print(f"  {label}: " + ", ".join(f"{name} {r[key] / total:.0%}" for name, key in shares))
    names = list(dict.fromkeys(name for r in measured for name in r.get("startup_phases_s", {})))
    table = []
    for r in measured:
        table.append({"task": r["task"], "process": r.get("process"), **r.get("startup_phases_s", {})})
    print("\nstart-up phases (s spent reaching each milestone from the one before):")
    _print_table(table, [("task", "task", ""), ("process", "process", "d")] + [(n, n, ".2f") for n in names])


def _suite_functions() -> dict[str, tuple[Callable[..., list[dict]], list]]:
    from . import suites

    return {
        "physics": (suites.physics, PHYSICS_COLUMNS),
        "env": (suites.env_step, ENV_COLUMNS),
        "inference": (suites.env_step_with_policy, ENV_COLUMNS),
        "train": (suites.train, TRAIN_COLUMNS),
        "solve": (suites.solve, SOLVE_COLUMNS),
    }


# the part-cost tools: ``simlab bench <tool> [<counter>] ...`` runs the module's main with the rest
TOOLS = {
    "startup": "simlab.benchmarks.startup",
    "viewer": "simlab.benchmarks.viewer_cost",
    "video": "simlab.benchmarks.video_cost",
    "terrain": "simlab.benchmarks.terrain_cost",
    "raycast": "simlab.benchmarks.ray_cast_cost",
    "postconstraint": "simlab.benchmarks.post_constraint_cost",
}
OP_COUNTERS = {
    "step": "simlab.benchmarks.step_ops",
    "update": "simlab.benchmarks.update_ops",
    "sync": "simlab.benchmarks.host_sync",
}


def _run_tool(argv: list[str]) -> int:
    """``simlab bench ops <counter> ...`` or ``simlab bench <tool> ...``."""
    import importlib

    if argv[0] == "ops":
        if len(argv) < 2 or argv[1] not in OP_COUNTERS:
            got = argv[1] if len(argv) > 1 else "nothing"
            print(f"simlab bench ops: give one of {list(OP_COUNTERS)} (got {got})", file=sys.stderr)
            return 2
        module, rest = OP_COUNTERS[argv[1]], argv[2:]
    else:
        module, rest = TOOLS[argv[0]], argv[1:]
    return importlib.import_module(module).main(rest) or 0


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv and (argv[0] in TOOLS or argv[0] == "ops"):
        return _run_tool(argv)
    parser = argparse.ArgumentParser(
        prog="simlab bench", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument(
        "suites", nargs="*", choices=[[], *SUITES], default=[], help=f"suites to run (default: {DEFAULT_SUITES})"
    )
    parser.add_argument("--device", default=None, help="cpu or cuda:N (default: the GPU when there is one)")
    parser.add_argument("--num_envs", type=int, nargs="+", default=None, help="env counts (default: by device)")
    parser.add_argument("--robots", nargs="+", choices=ROBOTS, default=list(ROBOTS), help="physics suite robots")
    parser.add_argument("--tasks", nargs="+", default=None, help="env/train suite tasks (Gymnasium ids)")
    parser.add_argument("--steps", type=int, default=None, help="timed steps per round")
    parser.add_argument("--iterations", type=int, default=10, help="timed training iterations")
    solve = parser.add_argument_group("solve suite")
    solve.add_argument("--library", default="rsl_rl", help="RL library that trains (rsl_rl)")
    solve.add_argument("--max_iterations", type=int, default=None, help="give up after (default: the agent's)")
    solve.add_argument("--eval_every", type=int, default=None, help="iterations between evaluated checkpoints")
    solve.add_argument("--seed", type=int, default=42, help="training seed")
    solve.add_argument("--eval_envs", type=int, default=64, help="envs that play each checkpoint")
    solve.add_argument("--eval_seconds", type=float, default=5.0, help="seconds of play per checkpoint")
    solve.add_argument("--reward_threshold", type=float, default=None, help="solved at this mean reward per step")
    solve.add_argument("--log_root", default="logs", help="where the training runs go")
    solve.add_argument("--resume", default=None, help="train on from this checkpoint (simlab train's --checkpoint)")
    solve.add_argument(
        "--processes",
        type=int,
        default=0,
        help="run each solve N times, one fresh process after the other (default 0: once, in this process); "
        "the first fills the caches the later ones start with",
    )
    solve.add_argument(
        "--pycache_prefix",
        default=None,
        metavar="DIR",
        help="with --processes: Python keeps every module's bytecode in DIR (PYTHONPYCACHEPREFIX, "
        "PYTHONDONTWRITEBYTECODE unset), as an installed package has it",
    )
    solve.add_argument(
        "--warp_cache",
        default=None,
        metavar="DIR",
        help="with --processes: Warp's kernel cache folder (WARP_CACHE_PATH); an empty one makes the first run cold",
    )
    solve.add_argument(
        "--overrides",
        nargs="+",
        default=[],
        metavar="KEY=VALUE",
        help="env.* / agent.* overrides as `simlab train` takes them (solve: the evaluation env gets the env.* ones; "
        "env and inference: each task's env is built with the env.* ones, e.g. env.sim.mujoco.njmax=96)",
    )
    solve.add_argument(
        "--allow_module",
        action="append",
        default=[],
        metavar="MODULE",
        help="let 'module:name' values in --overrides name MODULE's functions (beside simlab's and the task's)",
    )
    parser.add_argument(
        "--cuda_graph",
        choices=["on", "off", "both"],
        default="on",
        help="GPU fast path for env steps: replay each step as one CUDA graph (on), eager (off), or both",
    )
    parser.add_argument(
        "--ppo_update",
        choices=("default", "fast", "rsl_rl"),
        default="default",
        help="train/solve: simlab's fast PPO update (one CUDA graph per update) and, on CUDA, the rollout's "
        "policy as a CUDA graph; rsl_rl's own update and act; or the agent config's choice (agent.fast_update, "
        "agent.graph_act: both on CUDA)",
    )
    parser.add_argument("--json", default=None, help="write the results to this JSON file")
    args = parser.parse_args(argv)
    if args.processes < 0:
        parser.error(f"--processes takes a count >= 0, got {args.processes}")
    if (args.pycache_prefix or args.warp_cache) and not args.processes:
        parser.error("--pycache_prefix and --warp_cache set up fresh processes: give --processes N (N >= 1)")
    if any(n < 1 for n in args.num_envs or []):
        parser.error(f"--num_envs takes counts >= 1, got {args.num_envs}")
    if args.steps is not None and args.steps < 1:
        parser.error(f"--steps takes a count >= 1, got {args.steps}")
    if args.tasks:
        from simlab.tasks.utils.parse_cfg import task_spec

        for task in args.tasks:
            task_spec(task)  # an unknown id: one error naming the closest registered ones, before any measurement

    from simlab.utils.device import resolve_device

    device = resolve_device(args.device)
    gpu = device.startswith("cuda")
    default_envs = [None] if args.suites == ["solve"] else [1024, 4096, 16384, 65536] if gpu else [256, 1024]
    num_envs = args.num_envs or default_envs
    steps = args.steps or (200 if gpu else 50)
    chosen = args.suites or list(DEFAULT_SUITES)
    functions = _suite_functions()
    results: dict[str, list[dict]] = {}
    for name in chosen:
        fn, columns = functions[name]
        print(f"\n== {name} ({device}) ==", flush=True)
        rows = fn(
            device=device,
            num_envs=num_envs,
            steps=steps,
            robots=args.robots,
            tasks=args.tasks,
            iterations=args.iterations,
            graphs={"on": [True], "off": [False], "both": [True, False]}[args.cuda_graph],
            solve_args=args,
            fast_update={"default": None, "fast": True, "rsl_rl": False}[args.ppo_update],
        )
        _print_table(rows, columns)
        if name == "solve":
            _print_solve_breakdown(rows)
        results[name] = rows
    failed = sum("error" in row for rows in results.values() for row in rows)
    if args.json:
        meta = {"device": device, "machine": platform.node(), "cpu_count": os.cpu_count()}
        if gpu:
            import torch

            meta["gpu"] = torch.cuda.get_device_name()
        with open(args.json, "w") as f:
            json.dump({"meta": meta, "results": results}, f, indent=2)
        print(f"\nwrote {args.json}")
    if failed:
        print(f"\nsimlab bench: {failed} measurement(s) failed: their errors are above", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
