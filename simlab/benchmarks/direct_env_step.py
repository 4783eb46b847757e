"""Env steps per second of a direct-workflow task under random actions.

``bench_direct_env(cfg, num_envs, device, steps)`` builds the task from its config (the env class
is found next to the config: ``FooEnvCfg`` -> ``FooEnv`` in the same module, or pass
``env_class``), resets it, warms up, then times ``steps`` env steps with uniform random actions in
[-1, 1]. The figure includes everything the task does per step: decimated physics, rewards, dones,
resets and observations. Multi-agent configs (``DirectMARLEnvCfg``) get one action per agent.
"""

from __future__ import annotations

import importlib
import time

import gymnasium as gym
import torch

from .timing import gpu_memory_mb, synchronize


def env_class_of(cfg) -> type:
    """The env class that sits beside the config class (``CartpoleEnvCfg`` -> ``CartpoleEnv``)."""
    cfg_type = type(cfg)
    name = cfg_type.__name__.removesuffix("Cfg")
    env_class = getattr(importlib.import_module(cfg_type.__module__), name, None)
    if env_class is None:
        raise ValueError(
            f"No env class '{name}' next to {cfg_type.__name__} in {cfg_type.__module__}; pass env_class=..."
        )
    return env_class


def _action_sampler(env):
    """A function returning uniform random actions in [-1, 1] shaped for ``env.step``."""
    n, dev = env.num_envs, env.device
    if hasattr(env, "possible_agents"):
        dims = {a: gym.spaces.flatdim(env.action_spaces[a]) for a in env.possible_agents}
        return lambda: {a: torch.rand(n, d, device=dev) * 2 - 1 for a, d in dims.items()}
    dim = gym.spaces.flatdim(env.single_action_space)
    return lambda: torch.rand(n, dim, device=dev) * 2 - 1


def bench_direct_env(
    cfg, num_envs: int, device: str, steps: int, warmup: int = 20, env_class: type | None = None
) -> dict:
    """Time ``steps`` env steps of the task ``cfg`` describes; returns the figures as a dict."""
    cfg = cfg.copy()
    cfg.scene.num_envs = num_envs
    cfg.sim.device = device
    if cfg.seed is None:
        cfg.seed = 0
    env_class = env_class or env_class_of(cfg)

    start = time.perf_counter()
    env = env_class(cfg)
    env.reset()
    setup_s = time.perf_counter() - start
    try:
        sample = _action_sampler(env)
        for _ in range(warmup):
            env.step(sample())
        synchronize(env.device)
        start = time.perf_counter()
        for _ in range(steps):
            env.step(sample())
        synchronize(env.device)
        elapsed = time.perf_counter() - start
        env_steps_per_s = steps * num_envs / elapsed
        return {
            "task": type(env).__name__,
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
