"""Utilities: config classes, torch math, history buffers, name matching, io, seeding, datasets.

The names Isaac Lab exports from ``isaaclab.utils`` are here too. The torch-based parts (``math``,
``buffers``, ``types``, ``datasets``, ``array``, ``interpolation`` and the classes in them) are
imported on first use, so that ``from simlab.utils import configclass`` stays light.
"""

import importlib
from typing import Any

from simlab.utils import assets, dict, io, string  # noqa: F401  (submodules, as in Isaac Lab)
from simlab.utils.configclass import MISSING, configclass, is_configclass
from simlab.utils.dict import (
    class_to_dict,
    convert_dict_to_backend,
    dict_to_md5_hash,
    print_dict,
    replace_slices_with_strings,
    replace_strings_with_slices,
    update_class_from_dict,
    update_dict,
)
from simlab.utils.instantiate import instantiate
from simlab.utils.seed import set_seed
from simlab.utils.string import (
    ResolvableString,
    callable_to_string,
    clear_resolve_matching_names_cache,
    find_root_prim_path_from_regex,
    find_unique_string_name,
    is_lambda_expression,
    resolve_matching_names,
    resolve_matching_names_values,
    string_to_callable,
    string_to_slice,
    to_camel_case,
    to_snake_case,
)
from simlab.utils.timer import Timer

_LAZY_MODULES = {"array", "buffers", "datasets", "interpolation", "math", "modifiers", "noise", "types"}
_LAZY_NAMES = {
    "CircularBuffer": "simlab.utils.buffers",
    "DelayBuffer": "simlab.utils.buffers",
    "TimestampedBuffer": "simlab.utils.buffers",
    "ArticulationActions": "simlab.utils.types",
    "LinearInterpolation": "simlab.utils.interpolation",
    "TENSOR_TYPES": "simlab.utils.array",
    "TENSOR_TYPE_CONVERSIONS": "simlab.utils.array",
    "TensorData": "simlab.utils.array",
    "convert_to_torch": "simlab.utils.array",
    **{
        name: "simlab.utils.modifiers"
        for name in ("ModifierCfg", "ModifierBase", "DigitalFilter", "DigitalFilterCfg", "Integrator", "IntegratorCfg")
    },
    **{name: "simlab.utils.modifiers" for name in ("bias", "clip", "scale")},
}

__all__ = [
    "MISSING",
    "ResolvableString",
    "Timer",
    "assets",
    "callable_to_string",
    "class_to_dict",
    "clear_resolve_matching_names_cache",
    "configclass",
    "instantiate",
    "convert_dict_to_backend",
    "dict",
    "dict_to_md5_hash",
    "find_root_prim_path_from_regex",
    "find_unique_string_name",
    "io",
    "is_configclass",
    "is_lambda_expression",
    "print_dict",
    "replace_slices_with_strings",
    "replace_strings_with_slices",
    "resolve_matching_names",
    "resolve_matching_names_values",
    "set_seed",
    "string",
    "string_to_callable",
    "string_to_slice",
    "to_camel_case",
    "to_snake_case",
    "update_class_from_dict",
    "update_dict",
    *sorted(_LAZY_MODULES),
    *sorted(_LAZY_NAMES),
]


def __getattr__(name: str) -> Any:
    if name in _LAZY_MODULES:
        return importlib.import_module(f"simlab.utils.{name}")
    if name in _LAZY_NAMES:
        return getattr(importlib.import_module(_LAZY_NAMES[name]), name)
    raise AttributeError(f"module 'simlab.utils' has no attribute '{name}'")
