"""``isaaclab.utils`` of Isaac Lab 3.0: simlab's utilities; :mod:`simlab.v3.utils.math` takes (x, y, z, w)."""

from __future__ import annotations

from typing import Any

import simlab.utils as _utils
from simlab.v3.utils import math  # noqa: F401  (the submodule, as in Isaac Lab)

__all__ = ["math", *_utils.__all__]


def __getattr__(name: str) -> Any:
    return getattr(_utils, name)
