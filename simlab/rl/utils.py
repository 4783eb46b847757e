"""Helpers shared by the library wrappers: optional imports and observation/space handling."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import torch

from simlab.utils.optional import require

__all__ = [
    "check_single_agent",
    "image_history_terms",
    "is_multi_agent",
    "require",
    "stack_image_history",
    "unwrapped_env",
]


def unwrapped_env(env: Any) -> Any:
    """The simlab environment below any Gymnasium wrappers (``gym.make`` adds some)."""
    return env.unwrapped if hasattr(env, "unwrapped") else env


def is_multi_agent(env: Any) -> bool:
    """True for a multi-agent (DirectMARLEnv-like) environment."""
    return hasattr(unwrapped_env(env), "possible_agents")


def check_single_agent(env: Any, wrapper: str) -> Any:
    """Return the unwrapped env, or fail with a hint if it is a multi-agent env or not a vector env."""
    if not isinstance(env, gym.Env):
        raise TypeError(
            f"{wrapper} expects a Gymnasium env made with gym.make(task_id, cfg=env_cfg), got {type(env).__name__}."
        )
    base = unwrapped_env(env)
    if is_multi_agent(base):
        raise ValueError(
            f"{wrapper} needs a single-agent env, but {type(base).__name__} has agents {base.possible_agents}."
            " Convert it first: env = simlab.envs.multi_agent_to_single_agent(env)."
        )
    for attr in ("num_envs", "device", "single_observation_space", "single_action_space"):
        if not hasattr(base, attr):
            raise TypeError(f"{wrapper}: {type(base).__name__} is not a simlab vector env (it has no '{attr}').")
    return base


def stack_image_history(value: torch.Tensor) -> torch.Tensor:
    """An image term's history of k, ``(N, k, H, W, C)`` (``history_length=k``,
    ``flatten_history_dim=False``), as one ``(N, H, W, k * C)`` image: the images stacked along the
    channels, oldest first. Any other tensor is returned as it is."""
    if value.ndim != 5:
        return value
    n, k, h, w, c = value.shape
    return value.permute(0, 2, 3, 1, 4).reshape(n, h, w, k * c)


def image_history_terms(env: Any) -> dict[str, tuple[int, ...]]:
    """The observation terms (``"group/term"``) of a manager-based env that give an image's history,
    ``(k, H, W, C)`` per env (``history_length=k`` and ``flatten_history_dim=False`` on an image
    term), with that shape; empty for an env without such terms or without an observation manager."""
    manager = getattr(unwrapped_env(env), "observation_manager", None)
    if manager is None:
        return {}
    terms = {}
    for group, names in manager.active_terms.items():
        cfgs, dims = manager._group_obs_term_cfgs[group], manager.group_obs_term_dim[group]
        for name, cfg, dim in zip(names, cfgs, dims, strict=True):
            if cfg.history_length and not cfg.flatten_history_dim and len(dim) == 4:
                terms[f"{group}/{name}"] = tuple(dim)
    return terms
