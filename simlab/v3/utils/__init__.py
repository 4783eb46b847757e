"""``isaaclab.utils`` of Isaac Lab 3.0: simlab's utilities; :mod:`simlab.v3.utils.math` takes (x, y, z, w)."""

from __future__ import annotations

from typing import Any

import simlab.utils as _utils
from simlab.v3.utils import math  # noqa: F401  (the submodule, as in Isaac Lab)

__all__ = ["clone", "math", "replace", "replace_config", *_utils.__all__]


def replace_config(cfg: Any, **changes: Any) -> Any:
    """A copy of config ``cfg`` with ``changes`` set (Isaac Lab 3.0's ``isaaclab.utils.replace_config``,
    2.x's ``cfg.replace(...)``)."""
    return cfg.replace(**changes)


replace = replace_config
"""Isaac Lab 3.0's ``isaaclab.utils.replace(cfg, **changes)``, the same function."""


def clone(cfg: Any) -> Any:
    """A deep copy of config ``cfg`` (Isaac Lab 3.0's ``isaaclab.utils.clone``, 2.x's ``cfg.copy()``)."""
    return cfg.copy()


def __getattr__(name: str) -> Any:
    return getattr(_utils, name)
