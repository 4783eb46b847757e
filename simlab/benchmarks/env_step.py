"""Env steps per second of a manager-based task under random actions.

``bench_manager_env(task_cfg_factory, num_envs, device, steps)`` builds the task's config (a
config class or any function returning a ``ManagerBasedRLEnvCfg``), resets the env, warms up, then
times ``steps`` env steps with uniform random actions in [-1, 1]. The figure covers everything a
step does: decimated physics, terminations, rewards, resets and observations.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import torch

from .timing import gpu_memory_mb, synchronize


def bench_manager_env(
    task_cfg_factory: Callable[[], object], num_envs: int, device: str, steps: int, warmup: int = 20
) -> dict:
    """Time ``steps`` env steps of the task; returns the figures as a dict."""
    from simlab.envs import ManagerBasedRLEnv

    cfg = task_cfg_factory()
    cfg.scene.num_envs = num_envs
    cfg.sim.device = device
    if cfg.seed is None:
        cfg.seed = 0

    start = time.perf_counter()
    env = ManagerBasedRLEnv(cfg)
    env.reset()
    setup_s = time.perf_counter() - start
    try:
        actions = torch.empty(env.num_envs, env.action_manager.total_action_dim, device=env.device)
        for _ in range(warmup):
            env.step(actions.uniform_(-1.0, 1.0))
        synchronize(env.device)
        start = time.perf_counter()
        for _ in range(steps):
            env.step(actions.uniform_(-1.0, 1.0))
        synchronize(env.device)
        elapsed = time.perf_counter() - start
        env_steps_per_s = steps * num_envs / elapsed
        return {
            "task": type(cfg).__name__.removesuffix("Cfg"),
            "device": env.device,
            "backend": env.sim.physics.name,
            "num_envs": num_envs,
            "steps": steps,
            "decimation": cfg.decimation,
            "setup_s": setup_s,
            "step_ms": 1000.0 * elapsed / steps,
            "env_steps_per_s": env_steps_per_s,
            "physics_steps_per_s": env_steps_per_s * cfg.decimation,
            "gpu_memory_mb": gpu_memory_mb(env.device),
        }
    finally:
        env.close()
