"""``instantiate(cfg)``: the object a config describes (Isaac Lab 3.0's ``isaaclab.utils.instantiate``).

A config names its class with ``class_type`` (assets, sensors, actuators), or its config class is
registered here by the package that defines the class (the env configs, registered by
:mod:`simlab.envs` as ``"module:Class"`` strings, so nothing here imports a higher layer).
"""

from __future__ import annotations

import importlib
from typing import Any

from simlab.utils.errors import ConfigError

__all__ = ["instantiate", "register_instance_class"]

_CLASSES: dict[str, str] = {}  # "module.ConfigQualname" -> "module:Class"


def register_instance_class(cfg_class: str, target: str) -> None:
    """Make ``instantiate`` build configs of ``cfg_class`` (``"module.Qualname"``) as ``target`` (``"mod:Class"``)."""
    _CLASSES[cfg_class] = target


def instantiate(cfg: Any, **kwargs: Any) -> Any:
    """``cls(cfg, **kwargs)`` for the class ``cfg`` describes: its ``class_type``, else the class
    registered for its config class or the nearest base class."""
    cls = getattr(cfg, "class_type", None)
    if cls is None:
        for base in type(cfg).__mro__:
            target = _CLASSES.get(f"{base.__module__}.{base.__qualname__}")
            if target:
                module, _, name = target.partition(":")
                cls = getattr(importlib.import_module(module), name)
                break
    if cls is None:
        raise ConfigError(f"instantiate: {type(cfg).__name__} names no class to make (no class_type, none registered).")
    return cls(cfg, **kwargs)
