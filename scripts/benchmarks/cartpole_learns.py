"""Does each RL library learn the manager-based cartpole? Train with the task's default agent config,
then play the policy over 64 envs for 5 s and check that |pole angle| < 0.2 rad in >= 95% of steps.

    python scripts/benchmarks/cartpole_learns.py                       # all four libraries
    python scripts/benchmarks/cartpole_learns.py --libraries rsl_rl skrl

Training runs as ``simlab train --task simlab/Cartpole-v0 --library <lib> --headless`` in a child
process (its wall time is reported); the evaluation loads the newest checkpoint of that run.
``simlab bench solve`` measures the time to the first checkpoint that passes the same criterion.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time

from simlab.cli.main import build_parser
from simlab.cli.play import run_play
from simlab.tasks.utils.criteria import pole_angle_tracker

LIBRARIES = ("rsl_rl", "skrl", "sb3", "rl_games")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--libraries", nargs="+", choices=LIBRARIES, default=list(LIBRARIES))
    parser.add_argument("--task", default="simlab/Cartpole-v0")
    parser.add_argument("--num_envs", type=int, default=None, help="Training envs (default: the task's).")
    parser.add_argument("--max_iterations", type=int, default=None, help="Default: the agent config's.")
    parser.add_argument("--device", default=None)
    parser.add_argument("--log_root", default="logs")
    parser.add_argument("--eval_envs", type=int, default=64)
    parser.add_argument("--eval_seconds", type=float, default=5.0)
    parser.add_argument("--threshold", type=float, default=0.2, help="Pole angle bound [rad].")
    parser.add_argument("--fraction", type=float, default=0.95, help="Required fraction of steps inside.")
    parser.add_argument("--skip_training", action="store_true", help="Evaluate the newest runs only.")
    args = parser.parse_args()

    results = []
    for lib in args.libraries:
        train_cmd = [
            sys.executable,
            "-m",
            "simlab",
            "train",
            "--task",
            args.task,
            "--library",
            lib,
            "--headless",
            "--log_root",
            args.log_root,
            "--run_name",
            "learns",
        ]
        for flag in ("num_envs", "max_iterations", "device"):
            if getattr(args, flag) is not None:
                train_cmd += [f"--{flag}", str(getattr(args, flag))]
        wall = float("nan")
        if not args.skip_training:
            print(f"\n=== {lib}: {' '.join(train_cmd[1:])}", flush=True)
            start = time.time()
            proc = subprocess.run(train_cmd, env={**os.environ, "PYTHONUNBUFFERED": "1"})
            wall = time.time() - start
            if proc.returncode != 0:
                results.append((lib, wall, float("nan"), False))
                continue
        play_argv = [
            "play",
            "--task",
            args.task,
            "--library",
            lib,
            "--use_last_checkpoint",
            "--headless",
            "--num_envs",
            str(args.eval_envs),
            "--log_root",
            args.log_root,
            "--no_export",
        ]
        if args.device:
            play_argv += ["--device", args.device]
        play_args = build_parser().parse_args([*play_argv, "--seconds", str(args.eval_seconds)])
        on_step, counts = pole_angle_tracker(args.threshold)
        run_play(play_args, [], on_step=on_step)
        frac = counts["inside"] / max(1, counts["total"])
        results.append((lib, wall, frac, frac >= args.fraction))

    print(
        f"\n{args.task}: |pole angle| < {args.threshold} rad in >= {args.fraction:.0%} of steps "
        f"({args.eval_envs} envs, {args.eval_seconds} s)"
    )
    print(f"{'library':<10} {'train wall [s]':>14} {'inside':>8}  result")
    for lib, wall, frac, ok in results:
        print(f"{lib:<10} {wall:>14.1f} {frac:>8.1%}  {'PASS' if ok else 'FAIL'}")
    return 0 if all(ok for *_, ok in results) else 1


if __name__ == "__main__":
    sys.exit(main())
