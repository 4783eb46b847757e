"""``simlab random`` / ``simlab zero``: step a task with random or zero actions."""

from __future__ import annotations

import argparse

import gymnasium as gym
import torch

from simlab.cli.session import check_flags, load_configs, make_env

__all__ = ["run_random"]


def _sample(space: gym.Space, n: int, device: str, zero: bool) -> torch.Tensor:
    if zero:
        return torch.zeros((n, gym.spaces.flatdim(space)), device=device)
    if isinstance(space, gym.spaces.Box):
        low = torch.as_tensor(space.low, device=device).clamp(min=-1.0)
        high = torch.as_tensor(space.high, device=device).clamp(max=1.0)
        return low + (high - low) * torch.rand((n, *space.shape), device=device)
    return torch.as_tensor(space.sample(), device=device).repeat(n, 1)


def run_random(args: argparse.Namespace, zero: bool = False) -> int:
    """Step ``args.task`` with actions in [-1, 1] (within the action space) or zeros."""
    check_flags(args)
    args.library, args.algorithm = "rsl_rl", None
    env_cfg, _ = load_configs(args, [], with_agent=False)
    if args.seed is not None:
        env_cfg.seed = args.seed
    env = make_env(args, env_cfg, None, single_agent=False)
    base = env.unwrapped
    spaces = getattr(base, "action_spaces", None)
    print(f"[simlab] {args.task}: {base.num_envs} envs on {base.device}, {'zero' if zero else 'random'} actions")
    env.reset()
    step = 0
    try:
        while args.steps is None or step < args.steps:
            if spaces is not None:
                actions = {a: _sample(spaces[a], base.num_envs, base.device, zero) for a in base.possible_agents}
            else:
                actions = _sample(base.single_action_space, base.num_envs, base.device, zero)
            env.step(actions)
            step += 1
    except KeyboardInterrupt:
        pass
    finally:
        env.close()
    print(f"[simlab] {step} steps done")
    return 0
