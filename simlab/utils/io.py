"""Reading and writing configs: yaml (human-readable) and pickle (exact python objects)."""

from __future__ import annotations

import dataclasses
import os
import pickle
from typing import Any

import yaml

from simlab.utils.dict import MISSING_STR, _value_to_plain, class_to_dict

__all__ = ["dump_pickle", "dump_yaml", "load_pickle", "load_yaml"]


def _to_yaml_ready(value: Any) -> Any:
    """Plain dicts/lists/scalars only: callables -> "module:qualname", MISSING -> "???"."""
    value = _value_to_plain(value)
    if value is dataclasses.MISSING:
        return MISSING_STR
    if isinstance(value, dict):
        return {str(k): _to_yaml_ready(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_to_yaml_ready(v) for v in value]
    return value


def _prepare_path(filename: str | os.PathLike, ext: str) -> str:
    filename = os.fspath(filename)
    if not filename.endswith(ext) and not (ext == ".yaml" and filename.endswith(".yml")):
        filename += ext
    parent = os.path.dirname(filename)
    if parent:
        os.makedirs(parent, exist_ok=True)
    return filename


def dump_yaml(filename: str | os.PathLike, data: Any, sort_keys: bool = False) -> None:
    """Write a dict or a configclass to ``filename`` (``.yaml`` is appended if missing).

    Parent directories are created. Callables and classes are written as ``"module:qualname"``,
    tuples as lists, numpy/torch values as numbers or lists, ``MISSING`` as ``"???"``.
    """
    if dataclasses.is_dataclass(data) and not isinstance(data, type):
        data = class_to_dict(data)
    if not isinstance(data, dict):
        raise TypeError(f"dump_yaml expects a dict or a configclass instance, got {type(data).__name__}.")
    filename = _prepare_path(filename, ".yaml")
    with open(filename, "w") as f:
        yaml.safe_dump(_to_yaml_ready(data), f, default_flow_style=False, sort_keys=sort_keys)


def load_yaml(filename: str | os.PathLike) -> dict:
    """Read a yaml file into a dict (an empty file gives ``{}``)."""
    filename = os.fspath(filename)
    if not os.path.isfile(filename):
        raise FileNotFoundError(f"yaml file not found: '{filename}'.")
    with open(filename) as f:
        data = yaml.safe_load(f)
    return {} if data is None else data


def dump_pickle(filename: str | os.PathLike, data: Any) -> None:
    """Pickle ``data`` to ``filename`` (``.pkl`` is appended if missing; parent dirs are created)."""
    filename = _prepare_path(filename, ".pkl")
    with open(filename, "wb") as f:
        pickle.dump(data, f)


def load_pickle(filename: str | os.PathLike) -> Any:
    """Load a pickle file. Only load files you trust: unpickling can run arbitrary code."""
    filename = os.fspath(filename)
    if not os.path.isfile(filename):
        raise FileNotFoundError(f"pickle file not found: '{filename}'.")
    with open(filename, "rb") as f:
        return pickle.load(f)
