"""``SkrlVecEnvWrapper``: hand a simlab env to skrl.

simlab envs follow Isaac Lab's interface exactly (observation groups "policy"/"critic", single-env
spaces, ``state()`` for multi-agent critics), so skrl's own Isaac Lab wrappers fit; skrl's
``"auto"`` detection looks for ``isaaclab`` base classes, so ``"auto"`` is resolved here.
"""

from __future__ import annotations

import importlib
from typing import Any, Literal

import gymnasium as gym

from simlab.rl.utils import image_history_terms, is_multi_agent, require

__all__ = ["SkrlVecEnvWrapper"]

_WRAPPERS = ("auto", "isaaclab", "isaaclab-single-agent", "isaaclab-multi-agent")


def SkrlVecEnvWrapper(  # noqa: N802 - a function named like the class it returns, as in Isaac Lab
    env: gym.Env,
    ml_framework: Literal["torch", "jax", "jax-numpy"] = "torch",
    wrapper: Literal["auto", "isaaclab", "isaaclab-single-agent", "isaaclab-multi-agent"] = "isaaclab",
) -> Any:
    """Wrap ``env`` for skrl: a skrl ``Wrapper`` (single agent) or ``MultiAgentEnvWrapper``.

    Args:
        env: a simlab env made with ``gym.make`` (``ManagerBasedRLEnv``, ``DirectRLEnv`` or ``DirectMARLEnv``).
        ml_framework: skrl's backend. simlab's tensors are torch tensors, so "torch" is the one that
            runs without copies; "jax" goes through skrl's jax wrappers.
        wrapper: "auto"/"isaaclab" picks single- or multi-agent from the env; or name one explicitly.
    """
    if not isinstance(env, gym.Env):
        raise TypeError(f"SkrlVecEnvWrapper expects a Gymnasium env made with gym.make, got {type(env).__name__}.")
    if wrapper not in _WRAPPERS:
        raise ValueError(f"Unknown skrl wrapper '{wrapper}'. Allowed: {list(_WRAPPERS)}.")
    if ml_framework.startswith("torch"):
        module = "skrl.envs.wrappers.torch"
    elif ml_framework.startswith("jax"):
        module = "skrl.envs.wrappers.jax"
    else:
        raise ValueError(f"Unknown ml_framework '{ml_framework}'. Allowed: 'torch', 'jax', 'jax-numpy'.")
    _refuse_image_histories(env)
    require("skrl")
    wrap_env = importlib.import_module(module).wrap_env
    multi = is_multi_agent(env)
    if wrapper in ("auto", "isaaclab"):
        wrapper = "isaaclab-multi-agent" if multi else "isaaclab-single-agent"
    elif (wrapper == "isaaclab-multi-agent") != multi:
        kind = "multi-agent" if multi else "single-agent"
        raise ValueError(f"wrapper='{wrapper}' does not fit {type(env.unwrapped).__name__}, a {kind} env.")
    return wrap_env(env, wrapper=wrapper, verbose=False)


def _refuse_image_histories(env: gym.Env) -> None:
    """skrl hands a model its observation in the space's shape, and its image models (``permute`` to
    channels first, ``conv2d``) take one (H, W, C) image: an image term's history, (k, H, W, C), would
    fail deep in the model. rsl_rl's and rl_games' wrappers stack it into one image of k * C channels."""
    for term, shape in image_history_terms(env).items():
        if term.split("/")[0] in ("policy", "critic"):  # the groups skrl reads
            raise ValueError(
                f"skrl takes one image per observation, but term '{term}' gives the last {shape[0]} images"
                f" {shape} (history_length={shape[0]}, flatten_history_dim=False): train with rsl_rl or rl_games,"
                " which stack them along the channels, or set history_length=0."
            )
