"""Where a velocity policy's tracking error lies: the command's speed, and sway within the gait.

    python scripts/benchmarks/velocity_error_breakdown.py --task simlab/Velocity-Flat-Anymal-C-Play-v0 \
        --checkpoint logs/rsl_rl/anymal_c_flat/<run>/model_500.pt
    python scripts/benchmarks/velocity_error_breakdown.py --task simlab/Velocity-Flat-Unitree-Go2-Play-v0 \
        --checkpoint simlab/pretrained/Velocity-Flat-Unitree-Go2-v0/rsl_rl/model_299.pt

Plays the checkpoint (``--envs`` envs for ``--seconds``, the first ``--settle_seconds`` not counted)
and reports the criterion's number, the mean of |v_xy command - v_xy| (base frame) at every env step,
beside the same error of velocities averaged over windows of 0.2, 0.5 and 1 s: a policy that follows
the command but whose body sways with each step has a large instantaneous and a small windowed error.
Then the error by commanded speed, with the shortfall along the command (positive: slower than asked),
which separates a robot that cannot reach a speed from one that wobbles around it.
"""

from __future__ import annotations

import argparse
import os
import sys

import torch

from simlab.cli.main import build_parser
from simlab.cli.play import run_play

WINDOWS_S = (0.2, 0.5, 1.0)
SPEED_BINS = ((0.0, 0.25), (0.25, 0.5), (0.5, 0.75), (0.75, 1.0), (1.0, 2.0))


class VelocityLog:
    """An ``on_step`` hook for :func:`simlab.cli.play.run_play`: each step's command and base velocity
    (planar, base frame), from ``settle_seconds`` into the play on."""

    def __init__(self, settle_seconds: float):
        self.settle_seconds = settle_seconds
        self.steps = 0
        self.step_dt = float("nan")
        self.commands: list[torch.Tensor] = []
        self.velocities: list[torch.Tensor] = []

    def __call__(self, env, obs, actions) -> None:
        self.step_dt = env.step_dt
        if self.steps * env.step_dt >= self.settle_seconds:
            # copies: on the CPU .cpu() returns the env's own buffer, which the next step overwrites
            self.commands.append(env.command_manager.get_command("base_velocity")[:, :2].clone().cpu())
            self.velocities.append(env.scene["robot"].data.root_lin_vel_b[:, :2].clone().cpu())
        self.steps += 1


def windowed_error(commands: torch.Tensor, velocities: torch.Tensor, steps: int) -> float:
    """Mean |command - velocity| of both averaged over consecutive windows of ``steps`` env steps."""
    usable = (commands.shape[0] // steps) * steps
    mean = lambda x: x[:usable].reshape(-1, steps, *x.shape[1:]).mean(1)  # noqa: E731
    return float((mean(commands) - mean(velocities)).norm(dim=-1).mean())


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--task", required=True, help="A velocity task, e.g. simlab/Velocity-Flat-Anymal-C-Play-v0.")
    parser.add_argument("--checkpoint", required=True, help="An rsl_rl checkpoint of that task.")
    parser.add_argument("--envs", type=int, default=64)
    parser.add_argument("--seconds", type=float, default=7.0)
    parser.add_argument("--settle_seconds", type=float, default=1.0)
    parser.add_argument("--device", default="cpu")
    parser.add_argument("--seed", type=int, default=42)
    args = parser.parse_args()
    if not os.path.isfile(args.checkpoint):
        parser.error(f"--checkpoint {args.checkpoint}: no such file (an rsl_rl model_<iteration>.pt of the task)")
    if args.seconds <= args.settle_seconds:
        parser.error(f"--seconds ({args.seconds}) must be longer than --settle_seconds ({args.settle_seconds}).")

    play_argv = ["play", "--task", args.task, "--checkpoint", args.checkpoint, "--headless", "--no_export"]
    play_argv += ["--num_envs", str(args.envs), "--seconds", str(args.seconds), "--device", args.device]
    play_argv += ["--seed", str(args.seed)]
    log = VelocityLog(args.settle_seconds)
    run_play(build_parser().parse_args(play_argv), [], on_step=log)
    commands, velocities = torch.stack(log.commands), torch.stack(log.velocities)  # (steps, envs, 2)
    errors = (commands - velocities).norm(dim=-1)
    print(f"{args.task}, {args.envs} envs, {args.seconds - args.settle_seconds:g} s counted")
    print(f"mean |v_xy command - v_xy| at every step: {float(errors.mean()):.3f} m/s")
    for window in WINDOWS_S:
        error = windowed_error(commands, velocities, max(1, round(window / log.step_dt)))
        print(f"  of velocities averaged over {window:g} s: {error:.3f} m/s")
    speed = commands.norm(dim=-1)
    print("by commanded speed [m/s]: share of steps, mean error, shortfall along the command")
    for low, high in SPEED_BINS:
        inside = (speed >= low) & (speed < high)
        if not bool(inside.any()):
            continue
        along = (commands[inside] * (commands[inside] - velocities[inside])).sum(-1) / speed[inside].clamp(min=1e-3)
        share = float(inside.float().mean())
        print(f"  {low:.2f}-{high:.2f}: {share:5.1%}  {float(errors[inside].mean()):.3f}  {float(along.mean()):+.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
