"""``simlab random`` / ``simlab zero``: step a task with random or zero actions."""

from __future__ import annotations

import argparse
import os

import gymnasium as gym
import torch

from simlab.cli.session import check_flags, load_configs, make_env, resolve_seed
from simlab.envs.utils.spaces import sample_space

__all__ = ["run_random", "save_camera_frames"]

MAX_TILED_ENVS = 16
DEFAULT_SEED = 0  # as simlab record: a run without --seed repeats itself


def _sample(space: gym.Space, n: int, device: str, zero: bool) -> torch.Tensor:
    if zero:  # zeros of the action's own shape: (n, 1) for a Discrete space, a dict for a Dict one
        return sample_space(space, device, batch_size=n, fill_value=0)
    if isinstance(space, gym.spaces.Box):
        low = torch.as_tensor(space.low, device=device).clamp(min=-1.0)
        high = torch.as_tensor(space.high, device=device).clamp(max=1.0)
        return low + (high - low) * torch.rand((n, *space.shape), device=device)
    return sample_space(space, device, batch_size=n)  # one draw per env


def run_random(args: argparse.Namespace, zero: bool = False) -> int:
    """Step ``args.task`` with actions in [-1, 1] (within the action space) or zeros, ``args.steps``
    times or until Ctrl+C."""
    check_flags(args)
    args.library, args.algorithm = "rsl_rl", None
    env_cfg, _ = load_configs(args, [], with_agent=False)
    env_cfg.seed = resolve_seed(args.seed) if args.seed is not None else DEFAULT_SEED
    env = make_env(args, env_cfg, None, single_agent=False)
    base = env.unwrapped
    spaces = getattr(base, "action_spaces", None)
    until = f"{args.steps} steps" if args.steps is not None else "until Ctrl+C"
    print(
        f"[simlab] {args.task}: {base.num_envs} envs on {base.device}, {'zero' if zero else 'random'} actions, "
        f"seed {env_cfg.seed}, {until}"
    )
    env.reset()
    frames_dir = getattr(args, "save_camera_frames", None)
    if frames_dir is not None:
        for path in save_camera_frames(base, frames_dir, "reset"):
            print(f"[simlab] Camera images after the reset: {path}")
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
        if frames_dir is not None:
            for path in save_camera_frames(base, frames_dir, f"step{step:06d}"):
                print(f"[simlab] Camera images after {step} steps: {path}")
        env.close()
    print(f"[simlab] {step} steps done")
    return 0


def save_camera_frames(env, folder: str, label: str) -> list[str]:
    """Write one tiled PNG per camera sensor and image type of ``env`` (its first envs) to ``folder``;
    returns the paths written."""
    from simlab.sensors import Camera, save_images_to_file
    from simlab.utils.errors import ConfigError

    cameras = {name: sensor for name, sensor in env.scene.sensors.items() if isinstance(sensor, Camera)}
    if not cameras:
        raise ConfigError(
            f"--save_camera_frames: the task's scene has no camera (its sensors: {list(env.scene.sensors)});"
            " use a camera task such as simlab/Cartpole-RGB-Camera-Direct-v0"
        )
    paths = []
    for name, camera in cameras.items():
        for data_type, images in camera.data.output.items():
            path = os.path.join(folder, f"{name}_{data_type}_{label}.png")
            save_images_to_file(images[:MAX_TILED_ENVS], path)
            paths.append(path)
    return paths
