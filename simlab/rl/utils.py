"""Helpers shared by the library wrappers: optional imports and observation/space handling."""

from __future__ import annotations

from typing import Any

import gymnasium as gym

from simlab.utils.optional import require

__all__ = ["check_single_agent", "is_multi_agent", "require", "unwrapped_env"]


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
