"""Variants inside a config: Isaac Lab 3.0's ``PresetCfg`` and the resolution that picks one of each.

A ``PresetCfg`` subclass lists alternatives for one config slot as its fields; ``default`` is taken
when nothing else is asked for::

    @configclass
    class PhysicsCfg(PresetCfg):
        default: PhysxCfg = PhysxCfg()
        newton_mjwarp: NewtonCfg = NewtonCfg(solver_cfg=MJWarpSolverCfg(njmax=5))

    sim: SimulationCfg = SimulationCfg(physics=PhysicsCfg())

:func:`resolve_presets` replaces every ``PresetCfg`` of a config tree (dataclass fields, dicts, lists,
any depth) by one of its alternatives, a copy: the one named at its dotted path (``sim.physics=...``),
else the one a selected name gives (``presets=newton_mjwarp``), else ``default``. A chosen alternative
is walked again, so presets may nest. Names never match by guess: a selected name that no preset of
the tree has is reported back to the caller, which refuses it.
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from simlab.utils.configclass import configclass
from simlab.utils.errors import ConfigError

__all__ = ["PresetCfg", "collect_presets", "preset", "preset_alternatives", "resolve_presets"]


@configclass
class PresetCfg:
    """Base class of a config slot's variants: each field is one, ``default`` the one taken unasked.

    Fields whose names start with ``_`` are helpers, not variants (as in Isaac Lab 3.0)."""


def preset(**options: Any) -> PresetCfg:
    """A ``PresetCfg`` of the given alternatives, e.g. ``armature = preset(default=0.0, newton_mjwarp=0.01)``."""
    if "default" not in options:
        raise ConfigError(f"preset({', '.join(options)}) needs a 'default' alternative: preset(default=..., ...).")
    annotations = {k: Any for k in options}
    cls = configclass(type("_Preset", (PresetCfg,), {"__annotations__": annotations, **options}))
    return cls()


def preset_alternatives(node: PresetCfg) -> dict[str, Any]:
    """The alternatives of ``node`` by name. A value set on the instance (``MyPresets(default=...)``, an
    attribute assigned) wins; else the class attribute, since robot-specific modules reassign a preset
    class's fields after its instances were made."""
    cls = type(node)
    fields = node.__dataclass_fields__
    names = [f.name for f in dataclasses.fields(node)] + [n for n in vars(cls) if n not in fields]
    alternatives = {}
    for name in names:
        if name.startswith("_") or name in alternatives:
            continue
        value = getattr(cls, name, None)
        if callable(value) and not dataclasses.is_dataclass(value):
            continue  # methods and nested classes are helpers
        instance = getattr(node, name, None)
        if value is None or (name in fields and _set_on_instance(fields[name], instance)):
            value = instance
        alternatives[name] = value
    return alternatives


def _set_on_instance(field: dataclasses.Field, instance: Any) -> bool:
    """Whether the instance's value differs from the field's declared default (so it was given)."""
    if field.default is not dataclasses.MISSING:
        declared = field.default
    elif field.default_factory is not dataclasses.MISSING:
        declared = field.default_factory()
    else:
        return True
    try:
        return bool(instance != declared)
    except Exception:  # noqa: BLE001 - values without a plain truth value (arrays): compare identity
        return instance is not declared


def _children(value: Any) -> list[tuple[str, Any]]:
    if isinstance(value, Mapping):
        return [(str(k), v) for k, v in value.items()]
    if isinstance(value, list):
        return [(str(i), v) for i, v in enumerate(value)]
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return [(f.name, getattr(value, f.name, None)) for f in dataclasses.fields(value)]
    return []


def _set_child(parent: Any, key: str, value: Any) -> None:
    if isinstance(parent, Mapping):
        parent[key] = value
    elif isinstance(parent, list):
        parent[int(key)] = value
    else:
        setattr(parent, key, value)


def collect_presets(cfg: Any, path: str = "", _seen: set[int] | None = None) -> dict[str, dict[str, Any]]:
    """``{dotted path: {name: alternative}}`` of every preset in ``cfg``, those inside alternatives included."""
    seen = set() if _seen is None else _seen  # a config reached twice (shared) is walked once
    found: dict[str, dict[str, Any]] = {}
    for key, value in _children(cfg):
        if id(value) in seen:
            continue
        seen.add(id(value))
        child = f"{path}.{key}" if path else key
        if isinstance(value, PresetCfg):
            found[child] = preset_alternatives(value)
            for alternative in found[child].values():
                found.update(collect_presets(alternative, child, seen))
        else:
            found.update(collect_presets(value, child, seen))
    return found


def resolve_presets(
    cfg: Any,
    selected: Sequence[Sequence[str]] = (),
    paths: Mapping[str, str] | None = None,
    on_choice: Callable[[str, str, Any], None] | None = None,
) -> tuple[Any, set[str]]:
    """Replace every preset of ``cfg`` (in place; a preset at the root is returned in its stead) by one
    of its alternatives. Returns ``(cfg, names used)``.

    ``selected`` is a list of name groups, each in order of preference: at each preset, each group
    gives its first name the preset has; two groups giving different values is a ConfigError. ``paths``
    maps a dotted path to the name chosen there (it wins over ``selected``); ``on_choice(path, name,
    value)`` is told every choice made by name, and may refuse it.
    """
    paths = dict(paths or {})
    used: set[str] = set()

    def choose(node: PresetCfg, path: str) -> Any:
        alternatives = preset_alternatives(node)
        name = paths.pop(path, None)
        if name is not None and name not in alternatives:
            raise ConfigError(f"{path}={name}: not a preset there; its presets are {', '.join(alternatives)}.")
        if name is None:
            hits = []
            for group in selected:
                hit = next((n for n in group if n in alternatives), None)
                if hit is not None:
                    used.add(hit)
                    if hits and alternatives[hit] != alternatives[hits[0]]:
                        raise ConfigError(
                            f"presets {hits[0]} and {hit} both choose {path or 'the config'}, "
                            "differently: give one of them."
                        )
                    hits.append(hit)
            name = hits[0] if hits else None
        if name is not None and on_choice is not None:
            on_choice(path, name, alternatives[name])
        if name is None:
            if "default" not in alternatives:
                raise ConfigError(
                    f"{path or 'the config'} ({type(node).__name__}) has no 'default' preset and none was chosen: "
                    f"give one of {', '.join(alternatives)}."
                )
            name = "default"
        return copy.deepcopy(alternatives[name])

    visited: set[int] = set()  # a config reached twice (shared) is resolved once

    def resolve(value: Any, path: str) -> Any:
        seen = 0
        while isinstance(value, PresetCfg):
            seen += 1
            if seen > 32:
                raise ConfigError(f"{path}: presets choose presets in a cycle.")
            value = choose(value, path)
        if id(value) in visited:
            return value
        visited.add(id(value))
        for key, child in _children(value):
            child_path = f"{path}.{key}" if path else key
            new = resolve(child, child_path)
            if new is not child:
                _set_child(value, key, new)
        return value

    cfg = resolve(cfg, "")
    if paths:
        raise ConfigError(f"{', '.join(f'{p}={n}' for p, n in paths.items())}: no preset at that path.")
    return cfg, used
