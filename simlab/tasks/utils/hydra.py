"""Hydra-style command-line overrides of the env and agent configs.

``env.actions.joint_effort.scale=10 agent.seed=2024 env.rewards.alive=null +agent.params.x=1``:

* the first segment picks the config (``env`` or ``agent``), the rest walks fields / dict keys;
* values are read as YAML (``10`` int, ``0.5`` float, ``true``, ``[1, 2]``, ``null``, strings);
* ``null`` sets the field to None, which removes a manager term;
* a key that does not exist is an error naming the nearest valid keys; ``+`` adds a new dict key;
* a number field only takes numbers, a bool field only booleans.

This is a small parser with Hydra's override syntax, not Hydra itself: it never changes the working
directory nor writes ``outputs/``. :func:`hydra_task_config` gives Isaac Lab's decorator on top.
"""

from __future__ import annotations

import dataclasses
import functools
import re
import sys
from collections.abc import Callable, Sequence
from typing import Any

import yaml

from simlab.utils.dict import update_class_from_dict
from simlab.utils.errors import ConfigError
from simlab.utils.string import closest_matches

__all__ = ["OverrideError", "apply_overrides", "hydra_task_config", "parse_override"]

_ROOTS = ("env", "agent")
# a number in exponent form without a dot ("1e9", "-2E-3"): YAML 1.1 reads it as a string
_EXPONENT_NUMBER = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)[eE][+-]?\d+$")


class OverrideError(ConfigError):
    """A command-line override that names a wrong key or gives a wrong value."""


def parse_override(text: str) -> tuple[list[str], Any, bool]:
    """``"env.a.b=1"`` -> (``["env", "a", "b"]``, ``1``, add); ``add`` is True for ``+key=value``."""
    if "=" not in text:
        raise OverrideError(f"'{text}' is not an override. Use key=value, e.g. env.scene.num_envs=32 or agent.seed=1.")
    key, _, raw = text.partition("=")
    key = key.strip()
    add = key.startswith("+")
    key = key.lstrip("+")
    path = [p for p in key.split(".")]
    if not key or any(not p for p in path):
        raise OverrideError(f"'{text}': the key '{key}' is not a dotted path like env.rewards.alive.weight.")
    if path[0] not in _ROOTS:
        close = closest_matches(path[0], _ROOTS, n=1)
        hint = f" Did you mean '{close[0]}.{'.'.join(path[1:])}'?" if close else ""
        raise OverrideError(f"'{text}': overrides start with 'env.' or 'agent.', not '{path[0]}.'.{hint}")
    if len(path) < 2:
        raise OverrideError(f"'{text}': name a field inside '{path[0]}', e.g. {path[0]}.seed=1.")
    try:
        value = yaml.safe_load(raw) if raw.strip() else ""
    except yaml.YAMLError:
        value = raw  # not YAML: keep the text
    if isinstance(value, str) and _EXPONENT_NUMBER.match(value.strip()):
        value = float(value)
    return path, value, add


def _keys(obj: Any) -> list[str]:
    if isinstance(obj, dict):
        return [str(k) for k in obj]
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return [f.name for f in dataclasses.fields(obj)]
    return [k for k in vars(obj) if not k.startswith("_")] if hasattr(obj, "__dict__") else []


def _has(obj: Any, key: str) -> bool:
    return key in obj if isinstance(obj, dict) else key in _keys(obj)


def _get(obj: Any, key: str) -> Any:
    return obj[key] if isinstance(obj, dict) else getattr(obj, key)


def _unknown_key(text: str, dotted: str, key: str, obj: Any) -> OverrideError:
    valid = _keys(obj)
    close = closest_matches(key, valid, n=3, cutoff=0.4)
    hint = f" Nearest valid keys: {close}." if close else ""
    return OverrideError(f"'{text}': '{dotted}' has no key '{key}'.{hint} Valid keys: {valid}.")


def _declared_type(obj: Any, key: str) -> str | None:
    """The annotation of config field ``key`` as written (``"int"``, ``"float | None"``), None for dicts."""
    if not dataclasses.is_dataclass(obj):
        return None
    for f in dataclasses.fields(obj):
        if f.name == key:
            return f.type if isinstance(f.type, str) else getattr(f.type, "__name__", str(f.type))
    return None


def _check_type(text: str, current: Any, value: Any, declared: str | None = None) -> Any:
    if declared == "int" and isinstance(value, float) and not value.is_integer():
        raise OverrideError(f"'{text}': this field is an integer (int), got {value!r}.")
    if value is None or current is None or dataclasses.is_dataclass(current):
        return value
    if isinstance(current, bool):
        if not isinstance(value, bool):
            raise OverrideError(f"'{text}': expects true or false, got {value!r}.")
    elif isinstance(current, (int, float)):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise OverrideError(f"'{text}': expects a number, got {value!r}.")
        if isinstance(current, int) and isinstance(value, float) and value.is_integer():
            value = int(value)
    return value


def _apply_one(text: str, roots: dict[str, Any]) -> None:
    path, value, add = parse_override(text)
    obj = roots[path[0]]
    if obj is None:
        raise OverrideError(f"'{text}': there is no {path[0]} config to override.")
    for i, key in enumerate(path[1:-1], start=1):
        if not _has(obj, key):
            if add and isinstance(obj, dict):
                obj[key] = {}
            else:
                raise _unknown_key(text, ".".join(path[:i]), key, obj)
        obj = _get(obj, key)
        if obj is None:
            raise OverrideError(f"'{text}': '{'.'.join(path[: i + 1])}' is None (removed); cannot set inside it.")
    leaf = path[-1]
    parent = ".".join(path[:-1])
    if isinstance(obj, dict):
        if leaf not in obj and not add:
            raise _unknown_key(text, parent, leaf, obj)
        obj[leaf] = _check_type(text, obj.get(leaf), value)
        return
    if not _has(obj, leaf):
        raise _unknown_key(text, parent, leaf, obj)
    value = _check_type(text, getattr(obj, leaf), value, _declared_type(obj, leaf))
    try:
        # the configclass update resolves "module:function" strings, lists -> tuples, dicts -> configs
        update_class_from_dict(obj, {leaf: value}, _ns=parent)
    except (KeyError, ValueError, TypeError) as e:
        raise OverrideError(f"'{text}': {e}") from e


def apply_overrides(env_cfg: Any, agent_cfg: Any, overrides: Sequence[str]) -> None:
    """Apply Hydra-style ``overrides`` in place, in order (see the module docstring)."""
    roots = {"env": env_cfg, "agent": agent_cfg}
    for text in overrides:
        _apply_one(text, roots)


def hydra_task_config(task_name: str, agent_cfg_entry_point: str | None) -> Callable:
    """Decorate ``main(env_cfg, agent_cfg)``: load both configs of ``task_name`` from the registry,
    apply the overrides in ``sys.argv[1:]`` and call ``main`` with them (Isaac Lab's decorator).

    Scripts parse their own flags first and leave only the overrides in ``sys.argv``::

        args_cli, hydra_args = parser.parse_known_args()
        sys.argv = [sys.argv[0]] + hydra_args

        @hydra_task_config(args_cli.task, "rsl_rl_cfg_entry_point")
        def main(env_cfg, agent_cfg): ...
    """
    from .parse_cfg import load_cfg_from_registry

    def decorator(func: Callable) -> Callable:
        @functools.wraps(func)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            env_cfg = load_cfg_from_registry(task_name, "env_cfg_entry_point")
            agent_cfg = load_cfg_from_registry(task_name, agent_cfg_entry_point) if agent_cfg_entry_point else None
            apply_overrides(env_cfg, agent_cfg, sys.argv[1:])
            return func(env_cfg, agent_cfg, *args, **kwargs)

        return wrapper

    return decorator
