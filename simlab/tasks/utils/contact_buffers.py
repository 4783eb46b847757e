"""How many contacts and constraint rows a task's worlds use on MuJoCo Warp: what its config must reserve.

:func:`measure_task_buffers` runs a random-action rollout of the task with buffers far larger than
its config's (so that nothing overflows while measuring) and reads the peaks with
:class:`simlab.sim.backends.buffer_peaks.BufferPeaks`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import gymnasium as gym
import torch

from simlab.sim.backends.buffer_peaks import BufferPeaks

from .parse_cfg import parse_env_cfg

__all__ = ["measure_task_buffers"]


def measure_task_buffers(
    task: str,
    num_envs: int = 16,
    env_steps: int = 200,
    device: str = "cpu",
    seed: int = 0,
    headroom: int = 4,
    episode_length_s: float | None = None,
    configure: Callable[[Any], None] | None = None,
) -> tuple[BufferPeaks, int, dict[str, int]]:
    """Peak contacts and constraint rows of ``task`` over ``env_steps`` steps of uniform random
    actions in [-1, 1], on MuJoCo Warp (``device`` "cpu" runs its kernels on Warp's CPU device).

    The run reserves ``headroom`` times the task's configured buffers (or MuJoCo Warp's estimate
    where the task sets none), so that the measurement itself does not overflow.
    ``episode_length_s`` shortens the episodes so that the rollout crosses resets; ``configure``
    may change the env config further before the env is made.

    Returns the peaks, the number of worlds that diverged (their counts are not meaningful) and
    the sizes a run of the task reserves per world, ``{"nconmax": ..., "njmax": ...}`` (its config's,
    or the backend's estimate where it sets none), with its solver's ``"iterations"`` cap.
    """
    from simlab.sim.backends.cuda import CudaBackend  # needs mujoco-warp: imported when measuring

    cfg = parse_env_cfg(task, device=device, num_envs=num_envs)
    cfg.sim.engine = "mujoco_warp"
    cfg.sim.use_cuda_graph = False  # every physics step is sampled
    cfg.seed = seed
    if episode_length_s is not None:
        cfg.episode_length_s = episode_length_s
    if configure is not None:
        configure(cfg)
    env = gym.make(task, cfg=cfg).unwrapped
    try:
        if not isinstance(env.sim.physics, CudaBackend):
            raise TypeError(f"{task} did not run on MuJoCo Warp ({type(env.sim.physics).__name__})")
        # what a run of the task reserves: its config's sizes, or the backend's estimate
        configured = {"nconmax": env.sim.physics.nconmax, "njmax": env.sim.physics.njmax}
        iterations = cfg.sim.mujoco.iterations
        if headroom != 1:  # measure in a simulation with larger buffers
            env.close()
            cfg.sim.mujoco.nconmax = headroom * max(configured["nconmax"], 1)
            cfg.sim.mujoco.njmax = headroom * max(configured["njmax"], 1)
            env = gym.make(task, cfg=cfg).unwrapped
        backend = env.sim.physics
        env.reset(seed=seed)
        peaks = BufferPeaks().watch(backend)
        actions = torch.Generator(device=env.device).manual_seed(seed)
        # a multi-agent env takes all its agents' actions side by side in one tensor (env.action_space)
        space = getattr(env, "single_action_space", None) or env.action_space
        shape = (num_envs, space.shape[-1])
        for _ in range(env_steps):
            env.step(torch.rand(shape, generator=actions, device=env.device) * 2 - 1)
        backend.check_overflow()
        peaks.unwatch()
        return peaks, int(backend.diverged_count), {**configured, "iterations": iterations}
    finally:
        env.close()
