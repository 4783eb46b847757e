"""Environments: manager-based and direct RL environments, multi-agent ones, and their configs.

Names are imported on first use so that each workflow loads only what it needs.
"""

from __future__ import annotations

import importlib
from typing import Any

_EXPORTS = {
    "ViewerCfg": ".common",
    "VecEnvObs": ".common",
    "VecEnvStepReturn": ".common",
    "ManagerBasedEnv": ".manager_based_env",
    "ManagerBasedEnvCfg": ".manager_based_env_cfg",
    "ManagerBasedRLEnv": ".manager_based_rl_env",
    "ManagerBasedRLEnvCfg": ".manager_based_rl_env_cfg",
    "DirectRLEnv": ".direct_rl_env",
    "DirectRLEnvCfg": ".direct_rl_env_cfg",
    "DirectMARLEnv": ".direct_marl_env",
    "DirectMARLEnvCfg": ".direct_marl_env_cfg",
    "multi_agent_to_single_agent": ".utils.marl",
}

__all__ = sorted(_EXPORTS)


def _register_for_instantiate() -> None:
    """``simlab.utils.instantiate(env_cfg)`` makes the env of each env config class."""
    from simlab.utils.instantiate import register_instance_class

    for cfg_name in ("ManagerBasedEnvCfg", "ManagerBasedRLEnvCfg"):  # a direct env's class is the task's own
        env_name = cfg_name.removesuffix("Cfg")
        module = f"{__name__}{_EXPORTS[cfg_name]}"
        register_instance_class(f"{module}.{cfg_name}", f"{__name__}{_EXPORTS[env_name]}:{env_name}")


_register_for_instantiate()


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(importlib.import_module(_EXPORTS[name], __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
