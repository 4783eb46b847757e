"""Utilities: config classes, torch math, history buffers, name matching, io, seeding, datasets.

The torch-based parts (``math``, ``buffers``, ``types``, ``datasets`` and the buffer classes) are
imported on first use, so that ``from simlab.utils import configclass`` stays light.
"""

import importlib
from typing import Any

from simlab.utils import assets, dict, io, string  # noqa: F401  (submodules, as in Isaac Lab)
from simlab.utils.configclass import MISSING, configclass, is_configclass
from simlab.utils.seed import set_seed
from simlab.utils.timer import Timer

_LAZY_MODULES = {"math", "buffers", "types", "datasets"}
_LAZY_NAMES = {
    "CircularBuffer": "simlab.utils.buffers",
    "DelayBuffer": "simlab.utils.buffers",
    "TimestampedBuffer": "simlab.utils.buffers",
}

__all__ = [
    "MISSING",
    "CircularBuffer",
    "DelayBuffer",
    "TimestampedBuffer",
    "Timer",
    "assets",
    "buffers",
    "configclass",
    "datasets",
    "dict",
    "io",
    "is_configclass",
    "math",
    "set_seed",
    "string",
    "types",
]


def __getattr__(name: str) -> Any:
    if name in _LAZY_MODULES:
        return importlib.import_module(f"simlab.utils.{name}")
    if name in _LAZY_NAMES:
        return getattr(importlib.import_module(_LAZY_NAMES[name]), name)
    raise AttributeError(f"module 'simlab.utils' has no attribute '{name}'")
