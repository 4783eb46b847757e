"""Do the Franka manipulation tasks learn? Train with rsl_rl (the task's agent config), then play the
policy on held-out commands (another seed) and measure:

* reach (``simlab/Reach-Franka-v0``): the end-effector's position error [cm] and orientation error
  [rad] at the end of each 4 s command window; passes with mean < 2 cm and < 0.1 rad;
* lift (``simlab/Lift-Cube-Franka-v0``): episodes whose cube ends within 5 cm of the commanded
  position (measured on the episode's last step; a dropped cube fails); passes with >= 80 %;
* cabinet (``simlab/Franka-Cabinet-Direct-v0``): episodes that end with the top drawer open at least
  20 cm (its opening in the episode's final observation; an episode that pulls it past 39 cm ends
  there, open); passes with >= 80 %.

    python scripts/benchmarks/manipulation_learn.py                                   # both, GPU sizes
    python scripts/benchmarks/manipulation_learn.py --tasks reach --num_envs 4096 --max_iterations 1000
    python scripts/benchmarks/manipulation_learn.py --tasks cabinet --num_envs 4096  # the drawer, rsl_rl
    python scripts/benchmarks/manipulation_learn.py --tasks lift --num_envs 4096 --train_budget_s 420
                                            # lift: train for at most 7 minutes, evaluate what it reached
    python scripts/benchmarks/manipulation_learn.py --tasks reach lift cabinet --device cpu --num_envs 8 \\
        --max_iterations 2 --eval_envs 4 --eval_seconds 8                             # a CPU smoke run
    python scripts/benchmarks/manipulation_learn.py --tasks reach --log_root logs/reach_small \\
        agent.actor.hidden_dims=[64,64] agent.critic.hidden_dims=[64,64]  # a variant: Isaac Lab's sizes

Trailing ``env.x=v`` / ``agent.x=v`` overrides go to both the training and the evaluation (give each
variant its own ``--log_root``: the evaluation plays the newest run there).

Training runs as ``simlab train --task <task> --library rsl_rl --headless`` in a child process (its
wall time is reported); the evaluation loads the newest checkpoint of that run. With ``--train_budget_s``
the training is stopped (SIGTERM, on which it saves a checkpoint) once the budget is spent; the line
``=== evaluating ...`` names the checkpoint, whose number is the iterations reached.
"""

from __future__ import annotations

import argparse
import glob
import os
import signal
import subprocess
import sys
import time
from functools import partial
from typing import Any

import torch

from simlab.cli.main import EXIT_TERMINATED, build_parser
from simlab.cli.play import run_play
from simlab.tasks.manager_based.manipulation.lift.criterion import cube_near_goal
from simlab.tasks.manager_based.manipulation.reach.criterion import command_window_tracker
from simlab.tasks.utils.criteria import episode_end_tracker

TASKS = {
    "reach": "simlab/Reach-Franka-v0",
    "lift": "simlab/Lift-Cube-Franka-v0",
    "cabinet": "simlab/Franka-Cabinet-Direct-v0",
}


def reach_tracker(tolerance_cm: float, tolerance_rad: float):
    """Errors of the hand to its command on the last step of every command window (the solve criterion's hook)."""
    on_step, errors = command_window_tracker()

    def judge() -> tuple[str, bool]:
        if not errors["position"]:
            return "no command window ended: play longer (--eval_seconds)", False
        pos_cm, rot = torch.cat(errors["position"]) * 100, torch.cat(errors["orientation"])
        ok = pos_cm.mean() < tolerance_cm and rot.mean() < tolerance_rad
        text = (
            f"{pos_cm.numel()} commands: position error mean {pos_cm.mean():.2f} cm (median {pos_cm.median():.2f}),"
            f" orientation error mean {rot.mean():.3f} rad (median {rot.median():.3f})"
        )
        return text, bool(ok)

    return on_step, judge


def lift_tracker(tolerance_m: float, required: float):
    """Per finished episode: the cube within ``tolerance_m`` of its goal on the episode's last step (the
    solve criterion's hook; a dropped cube's episode counts as failed)."""
    on_step, counts = episode_end_tracker(partial(cube_near_goal, tolerance_m=tolerance_m))

    def judge() -> tuple[str, bool]:
        if not counts["episodes"]:
            return "no episode finished: play longer (--eval_seconds)", False
        rate = counts["success"] / counts["episodes"]
        return f"{counts['success']}/{counts['episodes']} episodes within {tolerance_m * 100:.0f} cm ({rate:.1%})", (
            rate >= required
        )

    return on_step, judge


def cabinet_tracker(min_opening_m: float, required: float):
    """Per finished episode: the top drawer open at least ``min_opening_m`` when the episode ended."""
    counts = {"success": 0, "episodes": 0}
    openings: list[torch.Tensor] = []

    def on_step(env, obs, actions) -> None:
        from simlab.tasks.direct.franka_cabinet.franka_cabinet_env import DRAWER_OPENING_OBS

        finished = env.reset_buf  # the envs whose episode ended in this step (already reset)
        if not bool(finished.any()):
            return
        opening = env.extras["final_obs"]["policy"][:, DRAWER_OPENING_OBS]
        counts["success"] += int((finished & (opening >= min_opening_m)).sum())
        counts["episodes"] += int(finished.sum())
        openings.append(opening[finished].cpu())

    def judge() -> tuple[str, bool]:
        if not counts["episodes"]:
            return "no episode finished: play longer (--eval_seconds)", False
        rate = counts["success"] / counts["episodes"]
        ends = torch.cat(openings) * 100
        text = (
            f"{counts['success']}/{counts['episodes']} episodes ended with the drawer open >= "
            f"{min_opening_m * 100:.0f} cm ({rate:.1%}); opening at the end mean {ends.mean():.1f} cm "
            f"(median {ends.median():.1f})"
        )
        return text, rate >= required

    return on_step, judge


def train(task: str, args) -> tuple[float, str | None]:
    """Train ``task`` in a child process: its wall time and, if it failed, why."""
    cmd = [sys.executable, "-m", "simlab", "train", "--task", task, "--library", "rsl_rl", "--headless"]
    cmd += ["--log_root", args.log_root, "--run_name", "learns"]
    for flag in ("num_envs", "max_iterations", "device"):
        if getattr(args, flag) is not None:
            cmd += [f"--{flag}", str(getattr(args, flag))]
    cmd += args.overrides
    print(f"\n=== {' '.join(cmd[2:])}", flush=True)
    start = time.time()
    proc = subprocess.Popen(cmd, env={**os.environ, "PYTHONUNBUFFERED": "1"})
    try:
        returncode = proc.wait(timeout=args.train_budget_s)
    except subprocess.TimeoutExpired:
        # SIGTERM makes `simlab train` save a checkpoint of the iteration it is in and exit (143)
        print(f"\n=== training budget of {args.train_budget_s:.0f} s reached: stopping it", flush=True)
        proc.send_signal(signal.SIGTERM)
        returncode = proc.wait()
        if returncode != EXIT_TERMINATED:
            return time.time() - start, f"training exited with {returncode} when stopped"
        checkpoint = newest_checkpoint(args.log_root)
        if checkpoint == "none" or os.path.getmtime(checkpoint) < start:
            return time.time() - start, "the training budget ended before training saved a checkpoint"
        return time.time() - start, None
    return time.time() - start, None if returncode == 0 else f"training exited with {returncode}"


def newest_checkpoint(log_root: str) -> str:
    """The newest rsl_rl checkpoint under ``log_root`` (what the evaluation plays)."""
    checkpoints = glob.glob(os.path.join(log_root, "**", "model_*.pt"), recursive=True)
    return max(checkpoints, key=os.path.getmtime) if checkpoints else "none"


def evaluate(task: str, tracker, args) -> dict[str, Any]:
    argv = ["play", "--task", task, "--library", "rsl_rl", "--use_last_checkpoint", "--headless"]
    argv += ["--num_envs", str(args.eval_envs), "--log_root", args.log_root, "--no_export", "--seed", str(args.seed)]
    argv += ["--seconds", str(args.eval_seconds)]
    if args.device:
        argv += ["--device", args.device]
    play_args = build_parser().parse_args(argv)
    on_step, judge = tracker
    run_play(play_args, args.overrides, on_step=on_step)
    return dict(zip(("text", "passed"), judge()))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tasks", nargs="+", choices=list(TASKS), default=list(TASKS))
    parser.add_argument("--num_envs", type=int, default=None, help="Training envs (default: the task's, 4096).")
    parser.add_argument("--max_iterations", type=int, default=None, help="Default: the agent config's.")
    parser.add_argument("--device", default=None)
    parser.add_argument("--log_root", default="logs")
    parser.add_argument("--eval_envs", type=int, default=256)
    parser.add_argument("--eval_seconds", type=float, default=20.0, help="Play time (reach: 5 windows of 4 s).")
    parser.add_argument("--seed", type=int, default=12345, help="Seed of the held-out evaluation commands.")
    parser.add_argument("--reach_cm", type=float, default=2.0)
    parser.add_argument("--reach_rad", type=float, default=0.1)
    parser.add_argument("--lift_m", type=float, default=0.05)
    parser.add_argument("--lift_rate", type=float, default=0.8)
    parser.add_argument("--cabinet_m", type=float, default=0.2, help="Drawer opening that counts as opened.")
    parser.add_argument("--cabinet_rate", type=float, default=0.8)
    parser.add_argument(
        "--train_budget_s",
        type=float,
        default=None,
        help="Stop training after this many seconds (it saves a checkpoint) and evaluate that checkpoint.",
    )
    parser.add_argument("--skip_training", action="store_true", help="Evaluate the newest runs only.")
    parser.add_argument("overrides", nargs="*", help="env.x=v / agent.x=v overrides for training and evaluation.")
    args = parser.parse_args()
    bad = [o for o in args.overrides if "=" not in o or not o.startswith(("env.", "agent."))]
    if bad:
        parser.error(f"overrides look like env.x.y=1 or agent.z=2, got {bad}")

    rows = []
    for name in args.tasks:
        task = TASKS[name]
        wall, failure = (float("nan"), None) if args.skip_training else train(task, args)
        if failure:
            rows.append((task, wall, failure, False))
            continue
        tracker = {
            "reach": lambda: reach_tracker(args.reach_cm, args.reach_rad),
            "lift": lambda: lift_tracker(args.lift_m, args.lift_rate),
            "cabinet": lambda: cabinet_tracker(args.cabinet_m, args.cabinet_rate),
        }[name]()
        print(f"=== evaluating {newest_checkpoint(args.log_root)}", flush=True)
        result = evaluate(task, tracker, args)
        rows.append((task, wall, result["text"], result["passed"]))

    print(f"\n{'task':<28} {'train wall [s]':>14}  result")
    for task, wall, text, ok in rows:
        print(f"{task:<28} {wall:>14.1f}  {'PASS' if ok else 'FAIL'}: {text}")
    return 0 if all(ok for *_, ok in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
