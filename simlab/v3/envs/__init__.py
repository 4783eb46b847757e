"""``isaaclab.envs`` of Isaac Lab 3.0: simlab's envs, made from configs whose quaternions are (x, y, z, w).

Each env class converts its config with :func:`simlab.v3._order.to_simlab` before simlab's own
constructor runs, so ``env.cfg`` and everything built from it hold simlab's (w, x, y, z), and builds
the scene's articulations, rigid objects and sensors with Isaac Lab 3.0's API
(:func:`simlab.v3.scene.with_v3_api`). The other names (the configs, ``mdp``,
``multi_agent_to_single_agent``, ...) are :mod:`simlab.envs`'s.
"""

from __future__ import annotations

import copy
from typing import Any

import simlab.envs as _envs
from simlab.utils.presets import PresetCfg, collect_presets, resolve_presets
from simlab.v3._order import replace_fields, to_simlab
from simlab.v3.scene import with_v3_api

__all__ = ["DirectMARLEnv", "DirectRLEnv", "ManagerBasedEnv", "ManagerBasedRLEnv", *_envs.__all__]


def _v3_cfg(cfg: Any) -> Any:
    """``cfg`` in simlab's order, its presets resolved (those no command line chose: their ``default``),
    its scene's entities with Isaac Lab 3.0's API. The user's ``cfg`` is not changed: presets are
    resolved in a copy (a config without presets is not copied, as the other steps copy only what they change)."""
    if isinstance(cfg, PresetCfg) or collect_presets(cfg):
        cfg, _ = resolve_presets(copy.deepcopy(cfg))
    cfg = to_simlab(cfg)
    scene = getattr(cfg, "scene", None)
    if scene is None:
        return cfg
    v3_scene = with_v3_api(scene)
    return cfg if v3_scene is scene else replace_fields(cfg, scene=v3_scene)


class ManagerBasedEnv(_envs.ManagerBasedEnv):
    def __init__(self, cfg: Any):
        super().__init__(_v3_cfg(cfg))


class ManagerBasedRLEnv(_envs.ManagerBasedRLEnv):
    def __init__(self, cfg: Any, render_mode: str | None = None, **kwargs: Any):
        super().__init__(_v3_cfg(cfg), render_mode, **kwargs)


class DirectRLEnv(_envs.DirectRLEnv):
    def __init__(self, cfg: Any, render_mode: str | None = None, **kwargs: Any):
        super().__init__(_v3_cfg(cfg), render_mode, **kwargs)


class DirectMARLEnv(_envs.DirectMARLEnv):
    def __init__(self, cfg: Any, render_mode: str | None = None, **kwargs: Any):
        super().__init__(_v3_cfg(cfg), render_mode, **kwargs)


def _register_for_instantiate() -> None:
    """``instantiate(env_cfg)`` makes these classes once 3.0 code imported them: they convert (x, y, z, w)
    configs and leave simlab's as they are."""
    from simlab.utils.instantiate import register_instance_class

    for env in (ManagerBasedEnv, ManagerBasedRLEnv):
        cfg_class = getattr(_envs, f"{env.__name__}Cfg")
        register_instance_class(f"{cfg_class.__module__}.{cfg_class.__qualname__}", f"{__name__}:{env.__name__}")


_register_for_instantiate()


def __getattr__(name: str) -> Any:
    if name == "mdp":  # 3.0's isaaclab.envs.mdp: this package's, whose orientations are (x, y, z, w)
        import importlib

        return importlib.import_module(f"{__name__}.mdp")
    return getattr(_envs, name)
