"""String helpers: regex name matching (joints, bodies, terms) and callable <-> "module:qualname"."""

from __future__ import annotations

import difflib
import importlib
import inspect
import re
from collections.abc import Callable, Sequence
from typing import Any

__all__ = [
    "callable_to_string",
    "closest_matches",
    "is_lambda_expression",
    "resolve_matching_names",
    "resolve_matching_names_values",
    "string_to_callable",
]


def closest_matches(word: str, candidates: Sequence[str], n: int = 3, cutoff: float = 0.5) -> list[str]:
    """The candidates most similar to ``word`` (difflib ratio), best first; empty if none is close."""
    return difflib.get_close_matches(str(word), [str(c) for c in candidates], n=n, cutoff=cutoff)


def _did_you_mean(word: str, candidates: Sequence[str]) -> str:
    close = closest_matches(word, candidates, n=1)
    return f" Did you mean '{close[0]}'?" if close else ""


def _as_key_list(keys: str | Sequence[str]) -> list[str]:
    if isinstance(keys, str):
        return [keys]
    keys = list(keys)
    for k in keys:
        if not isinstance(k, str):
            raise TypeError(f"Keys must be strings (regular expressions), got {k!r} of type {type(k).__name__}.")
    return keys


def _compile(key: str) -> re.Pattern:
    try:
        return re.compile(key)
    except re.error as e:
        raise ValueError(f"Key '{key}' is not a valid regular expression: {e}.") from e


def resolve_matching_names(
    keys: str | Sequence[str], list_of_strings: Sequence[str], preserve_order: bool = False
) -> tuple[list[int], list[str]]:
    """Match regex ``keys`` (full match) against ``list_of_strings``.

    Returns ``(indices, names)`` of the matched strings. By default they come in the order of
    ``list_of_strings``; with ``preserve_order=True`` in the order of the keys (strings matched
    by one key keep their order among themselves).

    Raises:
        ValueError: a key matches nothing, or one string is matched by more than one key.
    """
    keys = _as_key_list(keys)
    list_of_strings = list(list_of_strings)
    patterns = [_compile(k) for k in keys]

    matched_key_of: dict[int, int] = {}  # string index -> key index
    key_hits = [0] * len(keys)
    for s_idx, name in enumerate(list_of_strings):
        for k_idx, pattern in enumerate(patterns):
            if pattern.fullmatch(name):
                if s_idx in matched_key_of:
                    other = keys[matched_key_of[s_idx]]
                    raise ValueError(
                        f"Multiple keys match the string '{name}': '{other}' and '{keys[k_idx]}'."
                        " Each string may be matched by only one key."
                    )
                matched_key_of[s_idx] = k_idx
                key_hits[k_idx] += 1

    unmatched = [k for k, hits in zip(keys, key_hits) if hits == 0]
    if unmatched:
        hints = "".join(_did_you_mean(k, list_of_strings) for k in unmatched)
        raise ValueError(
            f"Not all regular expressions are matched! Unmatched keys: {unmatched}."
            f" Available strings: {list_of_strings}.{hints}"
        )

    if preserve_order:
        order = sorted(matched_key_of, key=lambda s_idx: (matched_key_of[s_idx], s_idx))
    else:
        order = sorted(matched_key_of)
    return order, [list_of_strings[i] for i in order]


def resolve_matching_names_values(
    data: dict[str, Any], list_of_strings: Sequence[str], preserve_order: bool = False
) -> tuple[list[int], list[str], list[Any]]:
    """Like :func:`resolve_matching_names`, with ``data`` mapping regex keys to values.

    Returns ``(indices, names, values)`` where ``values[i]`` is the value of the key that
    matched ``names[i]``. E.g. ``{".*_hip": 0.1, "knee": 0.5}`` gives one value per matched joint.
    """
    if not isinstance(data, dict):
        raise TypeError(f"Expected a dict of {{regex: value}}, got {type(data).__name__}: {data!r}.")
    keys = list(data.keys())
    indices, names = resolve_matching_names(keys, list_of_strings, preserve_order)
    patterns = [_compile(k) for k in keys]
    values = []
    for name in names:
        key = next(k for k, p in zip(keys, patterns) if p.fullmatch(name))
        values.append(data[key])
    return indices, names, values


def is_lambda_expression(obj: Any) -> bool:
    return inspect.isfunction(obj) and obj.__name__ == "<lambda>"


def callable_to_string(value: Callable) -> str:
    """``"module:qualname"`` for a function or class, e.g. ``"simlab.envs.mdp:joint_pos"``."""
    if not callable(value):
        raise ValueError(f"Expected a callable (function or class), got {type(value).__name__}: {value!r}.")
    if is_lambda_expression(value):
        raise ValueError(
            f"Cannot turn the lambda {value!r} into a 'module:qualname' string: lambdas have no importable"
            " name. Use a named function instead."
        )
    module = getattr(value, "__module__", None)
    qualname = getattr(value, "__qualname__", None) or getattr(value, "__name__", None)
    if module is None or qualname is None:
        # e.g. functools.partial or a callable instance: describe its type instead
        module, qualname = type(value).__module__, type(value).__qualname__
    return f"{module}:{qualname}"


def string_to_callable(name: str) -> Callable:
    """Resolve ``"module:qualname"`` (or ``"module.attr"``) to the object it names."""
    if not isinstance(name, str):
        raise TypeError(f"Expected a string 'module:qualname', got {type(name).__name__}: {name!r}.")
    if ":" in name:
        module_name, _, attr_path = name.partition(":")
    else:
        module_name, _, attr_path = name.rpartition(".")
    if not module_name or not attr_path:
        raise ValueError(
            f"Cannot resolve '{name}': expected 'module:qualname' (e.g. 'simlab.envs.mdp:joint_pos') or 'module.attr'."
        )
    try:
        obj: Any = importlib.import_module(module_name)
    except ImportError as e:
        raise ValueError(f"Cannot resolve '{name}': module '{module_name}' could not be imported ({e}).") from e
    for part in attr_path.split("."):
        if not hasattr(obj, part):
            public = [a for a in dir(obj) if not a.startswith("_")]
            raise ValueError(
                f"Cannot resolve '{name}': '{getattr(obj, '__name__', obj)}' has no attribute '{part}'."
                + _did_you_mean(part, public)
            )
        obj = getattr(obj, part)
    if not callable(obj):
        raise ValueError(f"'{name}' resolves to {obj!r}, which is not callable.")
    return obj
