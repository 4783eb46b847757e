"""How soon an in-hand task's hand loses the cube when nothing controls it: zero actions (every joint
target mid-range) and N(0, 1) actions (the noise PPO starts from), on the CPU.

    python scripts/tools/inhand_cube_falls.py --task simlab/Repose-Cube-Allegro-Direct-v0
    python scripts/tools/inhand_cube_falls.py --task simlab/Repose-Cube-Allegro-Direct-v0 \
        env.robot_cfg.actuators.fingers.stiffness=3.0 env.robot_cfg.actuators.fingers.friction=0.01

For each kind of action it prints the falls (terminations) over ``--steps`` env steps of ``--num_envs``
envs, the mean length of the episodes that ended, and each env's steps until its first fall
averaged with the envs that never fell counted at ``--steps``. Overrides are ``simlab train``'s
(``env.<path>=<value>``).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass


@dataclass
class Falls:
    falls: int
    """Episodes that ended in a termination (the cube fell, for these tasks)."""
    mean_ended_length: float
    """Mean length (env steps) of the episodes that ended, by termination or timeout; 0 if none did."""
    mean_first_fall: float
    """Each env's env steps until its first fall, averaged; an env that never fell counts the whole run."""


def cube_falls(env, actions: str, steps: int, seed: int) -> Falls:
    """Reset ``env`` (unwrapped) with ``seed`` and step it ``steps`` times with ``actions``: "zero" or "randn"."""
    import torch

    n, device = env.num_envs, env.device
    dim = env.action_manager.total_action_dim if hasattr(env, "action_manager") else env.single_action_space.shape[-1]
    env.reset(seed=seed)
    generator = torch.Generator(device=device).manual_seed(seed + 1)
    lengths: list[int] = []
    falls = 0
    first_fall = torch.full((n,), steps, dtype=torch.float)
    for step in range(steps):
        if actions == "zero":
            action = torch.zeros(n, dim, device=device)
        else:
            action = torch.randn(n, dim, generator=generator, device=device)
        length_before = env.episode_length_buf.clone()
        _, _, terminated, truncated, _ = env.step(action)
        for i in torch.nonzero(terminated | truncated).flatten().tolist():
            lengths.append(int(length_before[i]) + 1)
            if terminated[i]:
                falls += 1
                first_fall[i] = min(float(first_fall[i]), step + 1)
    mean_length = sum(lengths) / len(lengths) if lengths else 0.0
    return Falls(falls, mean_length, float(first_fall.mean()))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--task", required=True, help="Gymnasium id of an in-hand task.")
    parser.add_argument("--num_envs", type=int, default=32)
    parser.add_argument("--steps", type=int, default=120, help="Env steps per kind of action.")
    parser.add_argument("--seed", type=int, default=42)
    parser.add_argument("overrides", nargs="*", help="env.<path>=<value>, as simlab train takes them.")
    args = parser.parse_args(argv)

    import gymnasium as gym

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.tasks.utils import parse_env_cfg
    from simlab.tasks.utils.hydra import apply_overrides

    cfg = parse_env_cfg(args.task, device="cpu", num_envs=args.num_envs)
    cfg.seed = args.seed
    apply_overrides(cfg, None, args.overrides)
    env = gym.make(args.task, cfg=cfg).unwrapped
    try:
        print(f"{args.task} {' '.join(args.overrides)}: {args.num_envs} envs x {args.steps} steps")
        for actions in ("zero", "randn"):
            r = cube_falls(env, actions, args.steps, args.seed)
            print(
                f"  {actions:5s} actions: {r.falls:4d} falls, ended episodes {r.mean_ended_length:5.1f} steps long,"
                f" first fall after {r.mean_first_fall:5.1f} steps (never: {args.steps})"
            )
    finally:
        env.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
