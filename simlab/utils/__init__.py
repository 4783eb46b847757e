"""Utilities: config classes, torch math, name matching, io, seeding.

``simlab.utils.math`` (torch) is imported on first use, so that ``from simlab.utils import
configclass`` stays light.
"""

import importlib
from typing import Any

from simlab.utils import assets, dict, io, string  # noqa: F401  (submodules, as in Isaac Lab)
from simlab.utils.configclass import MISSING, configclass, is_configclass
from simlab.utils.seed import set_seed
from simlab.utils.timer import Timer

__all__ = [
    "MISSING",
    "Timer",
    "assets",
    "configclass",
    "dict",
    "io",
    "is_configclass",
    "math",
    "set_seed",
    "string",
]


def __getattr__(name: str) -> Any:
    if name == "math":
        return importlib.import_module("simlab.utils.math")
    raise AttributeError(f"module 'simlab.utils' has no attribute '{name}'")
