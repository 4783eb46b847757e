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
import sys

import torch

from simlab.cli.libraries import get_library
from simlab.cli.main import build_parser
from simlab.cli.session import load_configs, make_env

WINDOWS_S = (0.2, 0.5, 1.0)
SPEED_BINS = ((0.0, 0.25), (0.25, 0.5), (0.5, 0.75), (0.75, 1.0), (1.0, 2.0))


def play(task: str, checkpoint: str, envs: int, seconds: float, settle: float, device: str, seed: int):
    """Commands and base velocities (T, N, 2) of a play, and the env step [s]."""
    argv = ["play", "--task", task, "--headless", "--num_envs", str(envs), "--device", device, "--seed", str(seed)]
    args = build_parser().parse_args(argv)
    env_cfg, agent_cfg = load_configs(args, [])
    library = get_library("rsl_rl")
    library.configure(agent_cfg, args, env_cfg)
    env = make_env(args, env_cfg, None, single_agent=True)
    try:
        policy = library.load_policy(env, agent_cfg, checkpoint)
        base = env.unwrapped
        obs, _ = env.reset()
        commands, velocities = [], []
        for step in range(round(seconds / base.step_dt)):
            with torch.no_grad():
                obs, *_ = env.step(policy(obs))
            if step * base.step_dt >= settle:
                commands.append(base.command_manager.get_command("base_velocity")[:, :2].clone())
                velocities.append(base.scene["robot"].data.root_lin_vel_b[:, :2].clone())
        return torch.stack(commands).cpu(), torch.stack(velocities).cpu(), base.step_dt
    finally:
        env.close()


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
    if args.seconds <= args.settle_seconds:
        parser.error(f"--seconds ({args.seconds}) must be longer than --settle_seconds ({args.settle_seconds}).")

    commands, velocities, step_dt = play(
        args.task, args.checkpoint, args.envs, args.seconds, args.settle_seconds, args.device, args.seed
    )
    errors = (commands - velocities).norm(dim=-1)
    print(f"{args.task}, {args.envs} envs, {args.seconds - args.settle_seconds:g} s counted")
    print(f"mean |v_xy command - v_xy| at every step: {float(errors.mean()):.3f} m/s")
    for window in WINDOWS_S:
        steps = max(1, round(window / step_dt))
        print(f"  of velocities averaged over {window:g} s: {windowed_error(commands, velocities, steps):.3f} m/s")
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
