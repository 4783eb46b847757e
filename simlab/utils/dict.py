"""Dict helpers: config <-> dict conversion, recursive updates, pretty printing."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import re
import sys
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from simlab.utils.string import (
    ResolvableString,
    callable_to_string,
    closest_matches,
    is_lambda_expression,
    string_to_callable,
    string_to_slice,
)

__all__ = [
    "MISSING_STR",
    "callable_to_string",
    "class_to_dict",
    "convert_dict_to_backend",
    "dict_to_md5_hash",
    "print_dict",
    "replace_slices_with_strings",
    "replace_strings_with_slices",
    "string_to_callable",
    "update_class_from_dict",
    "update_dict",
]

# How a MISSING value is written to yaml (the same marker OmegaConf/Hydra use).
MISSING_STR = "???"

_CALLABLE_STR = re.compile(r"^[A-Za-z_][\w.]*:[A-Za-z_<][\w.<>]*$")
# fields that hold a callable even when currently unset (None / MISSING)
_CALLABLE_FIELDS = ("func", "class_type")


def _is_config_instance(obj: Any) -> bool:
    return dataclasses.is_dataclass(obj) and not isinstance(obj, type)


def _callable_name(value: Any) -> str:
    # lambdas have no importable name: keep a readable marker instead of failing the whole dump
    if is_lambda_expression(value):
        return f"{value.__module__}:{value.__qualname__}"
    module = getattr(value, "__module__", None) or type(value).__module__
    qualname = getattr(value, "__qualname__", None) or type(value).__qualname__
    return f"{module}:{qualname}"


def _value_to_plain(value: Any) -> Any:
    """Turn one config value into plain python (dicts, lists, scalars, strings)."""
    if value is None or value is dataclasses.MISSING or isinstance(value, (bool, int, float, str)):
        return value
    if _is_config_instance(value):
        return class_to_dict(value)
    if isinstance(value, slice):  # e.g. SceneEntityCfg.joint_ids = slice(None): "all"
        return f"slice({value.start}, {value.stop}, {value.step})"
    if isinstance(value, Mapping):
        return {k: _value_to_plain(v) for k, v in value.items()}
    if isinstance(value, tuple):  # kept a tuple, as Isaac Lab's class_to_dict does (yaml writers list it)
        return tuple(_value_to_plain(v) for v in value)
    if isinstance(value, (list, set, frozenset)):
        return [_value_to_plain(v) for v in value]
    if isinstance(value, type) or callable(value):
        return _callable_name(value)
    torch = sys.modules.get("torch")  # a tensor exists only once torch is imported: keep this module light
    if torch is not None and isinstance(value, torch.Tensor):  # kept, as Isaac Lab's (yaml writers list it)
        return value
    if hasattr(value, "tolist"):  # numpy arrays and scalars
        return value.tolist()
    if hasattr(value, "__dict__"):
        return class_to_dict(value)
    return value


def class_to_dict(obj: Any) -> dict[str, Any]:
    """Recursively convert a config (or any object with ``__dict__``) into a plain dict.

    Callables and classes become ``"module:qualname"`` strings, numpy arrays become lists; tuples
    and tensors stay as they are (Isaac Lab's), and ``simlab.utils.io.dump_yaml`` writes them as lists.
    """
    if _is_config_instance(obj):
        # the fields, then what __post_init__ added (Isaac Lab reads the instance's __dict__)
        names = [f.name for f in dataclasses.fields(obj)]
        names += [k for k in vars(obj) if k not in names and not k.startswith("__")]
        items = ((name, getattr(obj, name)) for name in names)
    elif isinstance(obj, Mapping):
        items = obj.items()
    elif hasattr(obj, "__dict__"):
        items = ((k, v) for k, v in vars(obj).items() if not k.startswith("__"))
    else:
        raise ValueError(f"Expected a config class instance, a dict or an object, got {type(obj).__name__}.")
    return {k: _value_to_plain(v) for k, v in items}


def _valid_keys(obj: Any) -> list[str]:
    if _is_config_instance(obj):
        return [f.name for f in dataclasses.fields(obj)]
    # a plain object: its own attributes and its class's (Isaac Lab accepts any existing attribute)
    keys = [k for k in vars(obj) if not k.startswith("__")]
    return keys + [k for k in vars(type(obj)) if not k.startswith("__") and k not in keys]


def _merge_value(current: Any, value: Any, path: str, field_default: Any = dataclasses.MISSING) -> Any:
    """The new value for a member currently holding ``current``, given ``value`` from a dict."""
    if value is None:
        return None  # None removes a term (e.g. ``rewards.alive = None``)
    if isinstance(value, str) and value == MISSING_STR:
        return dataclasses.MISSING
    if isinstance(value, Mapping):
        if current is None or current is dataclasses.MISSING:
            # the field was unset: rebuild its default config (if it has one) and fill it in
            if _is_config_instance(field_default):
                current = field_default
            else:
                return dict(value)
        if isinstance(current, dict):
            for k, v in value.items():
                current[k] = _merge_value(current[k], v, f"{path}.{k}") if k in current else v
            return current
        if _is_config_instance(current) or (hasattr(current, "__dict__") and not callable(current)):
            update_class_from_dict(current, value, _ns=path)
            return current
        raise ValueError(
            f"Cannot set '{path}' from a dict: the current value is {type(current).__name__} ({current!r})."
        )
    if _is_config_instance(current):
        raise ValueError(
            f"'{path}' holds a config of type {type(current).__name__}; expected a dict (to update it) or"
            f" None (to remove it), got {type(value).__name__}: {value!r}."
        )
    if isinstance(value, (list, tuple)):
        given = type(value)
        if isinstance(current, (list, tuple)) and len(current) == len(value):
            value = [
                _merge_value(c, v, f"{path}[{i}]") if isinstance(v, Mapping) and _is_config_instance(c) else v
                for i, (c, v) in enumerate(zip(current, value))
            ]
        # a tuple member stays a tuple; otherwise the given kind is kept (Isaac Lab's)
        return tuple(value) if isinstance(current, tuple) or given is tuple else list(value)
    if isinstance(value, ResolvableString):
        return value  # already a (lazy) callable reference: keep it as given
    if isinstance(value, str) and _CALLABLE_STR.match(value):
        leaf = path.rsplit(".", 1)[-1]
        unset = current is None or current is dataclasses.MISSING
        if (callable(current) and not isinstance(current, str)) or (unset and leaf in _CALLABLE_FIELDS):
            return string_to_callable(value)
    return value


def update_class_from_dict(obj: Any, data: Mapping[str, Any], _ns: str = "") -> None:
    """Update the members of ``obj`` (a config, a dict or an object) in place from ``data``.

    Nested configs are updated recursively; strings ``"module:qualname"`` given for a member that
    holds a callable are resolved to the callable; ``None`` removes a term; a key that is not a
    member raises a ``KeyError`` naming the key, the valid keys and the closest match.
    """
    if not isinstance(data, Mapping):
        raise TypeError(f"Expected a dict to update '{_ns or type(obj).__name__}', got {type(data).__name__}.")
    if isinstance(obj, dict):
        for key, value in data.items():
            path = f"{_ns}.{key}" if _ns else str(key)
            obj[key] = _merge_value(obj[key], value, path) if key in obj else value
        return

    fields = {f.name: f for f in dataclasses.fields(obj)} if _is_config_instance(obj) else {}
    valid = _valid_keys(obj)
    for key, value in data.items():
        path = f"{_ns}.{key}" if _ns else str(key)
        if key not in valid:
            close = closest_matches(str(key), valid, n=1)
            hint = f" Did you mean '{close[0]}'?" if close else ""
            raise KeyError(f"Key '{path}' is not a field of {type(obj).__name__}. Valid keys: {valid}.{hint}")
        current = getattr(obj, key)
        default = dataclasses.MISSING
        if isinstance(value, Mapping) and (current is None or current is dataclasses.MISSING) and key in fields:
            # the field is unset but a dict arrives: start from the field's default config, if any
            f = fields[key]
            default = f.default_factory() if f.default_factory is not dataclasses.MISSING else f.default
        setattr(obj, key, _merge_value(current, value, path, default))


def update_dict(orig_dict: dict, new_dict: Mapping) -> dict:
    """Recursively merge ``new_dict`` into ``orig_dict`` (nested dicts are merged, not replaced)."""
    for key, value in new_dict.items():
        if isinstance(value, Mapping) and isinstance(orig_dict.get(key), dict):
            update_dict(orig_dict[key], value)
        else:
            orig_dict[key] = value
    return orig_dict


def print_dict(val: Any, nesting: int = -4, start: bool = True) -> None:
    """Print a (nested) dict or config as an indented tree, callables as ``module:qualname``."""
    if _is_config_instance(val):
        val = class_to_dict(val)
    if isinstance(val, dict):
        if not start:
            print("")
        nesting += 4
        for key, item in val.items():
            print(nesting * " " + f"{key}: ", end="")
            print_dict(item, nesting, start=False)
    elif callable(val):
        print(_callable_name(val))
    else:
        print(val)


def dict_to_md5_hash(data: object) -> str:
    """MD5 hex digest of a dict (or config, via :func:`class_to_dict`), independent of key order."""
    plain = data if isinstance(data, dict) else class_to_dict(data)
    return hashlib.md5(json.dumps(plain, sort_keys=True, default=str).encode()).hexdigest()


def replace_slices_with_strings(data: Any) -> Any:
    """A copy of ``data`` (nested dicts, lists, tuples) with every ``slice`` written as ``"slice(a, b, c)"``."""
    if isinstance(data, dict):
        return {k: replace_slices_with_strings(v) for k, v in data.items()}
    if isinstance(data, (list, tuple)):
        return type(data)(replace_slices_with_strings(v) for v in data)
    if isinstance(data, slice):
        return f"slice({data.start},{data.stop},{data.step})"
    return data


def replace_strings_with_slices(data: Any) -> Any:
    """A copy of ``data`` with every ``"slice(a, b, c)"`` string turned back into a ``slice``."""
    if isinstance(data, dict):
        return {k: replace_strings_with_slices(v) for k, v in data.items()}
    if isinstance(data, (list, tuple)):
        return type(data)(replace_strings_with_slices(v) for v in data)
    if isinstance(data, str) and data.startswith("slice(") and data.endswith(")"):
        return string_to_slice(data)
    return data


def _array_kind(value: Any) -> str | None:
    if isinstance(value, np.ndarray):
        return "numpy"
    module = type(value).__module__
    if module.startswith("torch") and hasattr(value, "cpu"):
        return "torch"
    if module.startswith("warp"):
        return "warp"
    return None


def convert_dict_to_backend(
    data: dict,
    backend: str = "numpy",
    array_types: Iterable[str] = ("numpy", "torch", "warp"),
) -> dict:
    """A copy of a (nested) dict with its arrays of the given ``array_types`` turned into ``backend`` arrays.

    ``backend`` is ``"numpy"`` or ``"torch"`` (warp arrays are read through their ``numpy()``).
    Values that are not arrays are kept as they are.
    """
    if backend not in ("numpy", "torch"):
        raise ValueError(f"convert_dict_to_backend: backend must be 'numpy' or 'torch', got {backend!r}.")
    kinds = set(array_types)
    unknown = kinds - {"numpy", "torch", "warp"}
    if unknown:
        raise ValueError(f"convert_dict_to_backend: unknown array types {sorted(unknown)}; use numpy, torch, warp.")

    def convert(value: Any) -> Any:
        if isinstance(value, dict):
            return {k: convert(v) for k, v in value.items()}
        kind = _array_kind(value)
        if kind is None or kind not in kinds:
            return value
        array = (
            value.detach().cpu().numpy() if kind == "torch" else np.asarray(value.numpy() if kind == "warp" else value)
        )
        if backend == "numpy":
            return array
        import torch

        return value if kind == "torch" else torch.from_numpy(array)

    return convert(data)
