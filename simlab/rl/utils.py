"""Helpers shared by the library wrappers: optional imports and observation/space handling."""

from __future__ import annotations

import importlib
from types import ModuleType
from typing import Any

import gymnasium as gym

from simlab.utils.errors import MissingDependencyError

__all__ = ["check_single_agent", "is_multi_agent", "require", "unwrapped_env"]

# library module -> (pip distribution, simlab extra)
_LIBRARIES = {
    "rsl_rl": ("rsl-rl-lib", "rsl_rl"),
    "tensordict": ("tensordict", "rsl_rl"),
    "skrl": ("skrl", "skrl"),
    "stable_baselines3": ("stable-baselines3", "sb3"),
    "rl_games": ("rl-games", "rl_games"),
    "onnx": ("onnx", "train"),
    "onnxruntime": ("onnxruntime", "train"),
    "tensorboard": ("tensorboard", "train"),
    "tqdm": ("tqdm", "train"),
    "rich": ("rich", "sb3"),
    "imageio": ("imageio", "render"),
    "imageio_ffmpeg": ("imageio-ffmpeg", "render"),
    "moviepy": ("moviepy", "render"),
}


def require(module: str) -> ModuleType:
    """Import ``module``, or raise a ``MissingDependencyError`` (an ``ImportError``) naming its pip install."""
    try:
        return importlib.import_module(module)
    except ImportError as e:
        top = module.split(".")[0]
        dist, extra = _LIBRARIES.get(top, (top, "all"))
        raise MissingDependencyError(
            f"This feature needs the '{dist}' library, which is not installed ({e}). "
            f'Install it with: pip install "simlab[{extra}]"'
        ) from e


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
