"""``configclass``: the dataclass-based config decorator of Isaac Lab.

Compared to a plain ``@dataclass``:

* class attributes without annotations are fields too (``joint_pos = ObsTerm(func=...)``), in the
  order they are written; a subclass may give an inherited field a new default by plain assignment;
* mutable defaults (lists, dicts, nested configs) are deep-copied for every instance;
* ``MISSING`` marks a required field, yet the config can still be built without it:
  ``validate()`` lists every missing field by its dotted path;
* every config gets ``replace``, ``copy``, ``to_dict``, ``from_dict`` and ``validate``.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import inspect
import types
from collections.abc import Callable
from dataclasses import MISSING, Field
from typing import Any, ClassVar, TypeVar

from simlab.utils.dict import class_to_dict, update_class_from_dict
from simlab.utils.string import closest_matches

__all__ = ["MISSING", "MissingFieldError", "configclass", "is_configclass"]

T = TypeVar("T")

# Defaults of these types are shared safely between instances; anything else is deep-copied.
_SHARED_TYPES = (
    type(None), bool, int, float, complex, str, bytes, frozenset, range, type,
    types.FunctionType, types.BuiltinFunctionType, types.MethodType, functools.partial,
)  # fmt: skip


# ``x is MISSING`` must survive copy.deepcopy and pickle (config copies, default factories,
# dump_pickle). Reducing to the global name makes both hand back the singleton itself.
type(MISSING).__reduce__ = lambda self: "MISSING"


class MissingFieldError(TypeError, ValueError):
    """Raised by ``validate()`` when required (``MISSING``) fields were never set."""


def is_configclass(obj: Any) -> bool:
    """True for a configclass (or dataclass) type or instance."""
    return dataclasses.is_dataclass(obj)


def _return_missing() -> Any:
    return MISSING


def _is_classvar(annotation: Any) -> bool:
    if isinstance(annotation, str):
        return annotation.startswith(("ClassVar", "typing.ClassVar"))
    return annotation is ClassVar or getattr(annotation, "__origin__", None) is ClassVar


# -- methods added to every configclass ------------------------------------------------------------


def _replace(self: T, **kwargs: Any) -> T:
    """A deep copy of this config with the given fields changed (``__post_init__`` runs again)."""
    valid = [f.name for f in dataclasses.fields(self) if f.init]
    unknown = [k for k in kwargs if k not in valid]
    if unknown:
        hints = "".join(f" ('{k}': did you mean '{c[0]}'?)" for k in unknown if (c := closest_matches(k, valid, 1)))
        raise TypeError(
            f"{type(self).__name__}.replace() got unknown field(s) {unknown}.{hints} Valid fields: {valid}."
        )
    return dataclasses.replace(copy.deepcopy(self), **kwargs)


def _copy(self: T) -> T:
    """A deep copy of this config."""
    return copy.deepcopy(self)


def _to_dict(self) -> dict[str, Any]:
    """This config as nested plain dicts (callables and classes as ``"module:qualname"``)."""
    return class_to_dict(self)


def _from_dict(self, data: dict[str, Any]) -> None:
    """Update this config in place from a (nested) dict, e.g. one read back from yaml."""
    update_class_from_dict(self, data)


def _find_missing(value: Any, path: str, seen: set[int]) -> list[str]:
    if value is MISSING:
        return [path]
    if id(value) in seen:
        return []
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        seen.add(id(value))
        return [
            m
            for f in dataclasses.fields(value)
            for m in _find_missing(getattr(value, f.name), f"{path}.{f.name}" if path else f.name, seen)
        ]
    if isinstance(value, dict):
        seen.add(id(value))
        return [m for k, v in value.items() for m in _find_missing(v, f"{path}.{k}", seen)]
    if isinstance(value, (list, tuple)):
        seen.add(id(value))
        return [m for i, v in enumerate(value) for m in _find_missing(v, f"{path}[{i}]", seen)]
    return []


def _validate(self) -> None:
    """Raise :class:`MissingFieldError` listing every field (dotted path) still set to ``MISSING``."""
    missing = _find_missing(self, "", set())
    if missing:
        listing = "\n".join(f"  - {m}" for m in missing)
        raise MissingFieldError(f"{type(self).__name__} has {len(missing)} missing field(s) to set:\n{listing}\n")


def _post_init(self) -> None:
    """Nothing to do; there so that a subclass's ``__post_init__`` can call ``super().__post_init__()``
    whatever its bases (Isaac Lab's config classes all have one; its agent configs call it)."""


_METHODS: dict[str, Callable] = {
    "__post_init__": _post_init,
    "replace": _replace,
    "copy": _copy,
    "to_dict": _to_dict,
    "from_dict": _from_dict,
    "validate": _validate,
}


# -- class processing ------------------------------------------------------------------------------


def _inherited_fields(cls: type) -> dict[str, Field]:
    fields: dict[str, Field] = {}
    for base in reversed(cls.__mro__[1:]):
        if dataclasses.is_dataclass(base):
            fields.update({f.name: f for f in dataclasses.fields(base)})
    return fields


def _is_member_not_field(cls: type, key: str, value: Any, inherited: dict[str, Field]) -> bool:
    """True for class members that are not config values: methods, properties, nested classes."""
    if key.startswith("__") or key.startswith("_abc"):
        return True
    if any(value is m for m in _METHODS.values()):
        return True
    if isinstance(value, (staticmethod, classmethod, property, functools.cached_property)):
        return True
    if inspect.isfunction(value) and value.__name__ != "<lambda>":
        # a def in the class body is a method; a function assigned from elsewhere is a value
        return value.__qualname__.startswith(cls.__qualname__ + ".")
    if isinstance(value, type):
        # a class defined in the body is a nested class; one assigned from elsewhere is a value
        # (a field of type type[...]), and so is one that overrides an inherited field (class_type)
        nested = value.__qualname__ == f"{cls.__qualname__}.{value.__name__}"
        return nested and key not in inherited and key != "class_type"
    return False


def _process_class(cls: type) -> None:
    inherited = _inherited_fields(cls)
    own_ann: dict[str, Any] = dict(cls.__dict__.get("__annotations__", {}))

    # unannotated class attributes become fields; keep the order in which they were written
    value_keys = [k for k, v in cls.__dict__.items() if k in own_ann or not _is_member_not_field(cls, k, v, inherited)]
    ann_order = list(own_ann)
    annotations: dict[str, Any] = {}
    for key in value_keys:
        if key in own_ann:
            # annotation-only fields written before this one come first
            for a in ann_order[: ann_order.index(key) + 1]:
                annotations.setdefault(a, own_ann[a])
        elif key in inherited:
            annotations[key] = inherited[key].type  # subclass overrides an inherited default
        else:
            value = cls.__dict__[key]
            if value is MISSING:
                raise TypeError(
                    f"Missing type annotation for '{key}' in class '{cls.__name__}': MISSING says nothing of the"
                    f" field's type. Write '{key}: <type> = MISSING', or give a default value."
                )
            annotations[key] = Any if value is None else type[value] if isinstance(value, type) else type(value)
    for a in ann_order:
        annotations.setdefault(a, own_ann[a])

    for key, annotation in annotations.items():
        if _is_classvar(annotation):
            continue
        if key not in cls.__dict__:
            if key not in inherited:
                raise ValueError(
                    f"Missing default value for '{key}' in class '{cls.__name__}'. Give it a default, or"
                    f" '{key}: ... = MISSING' for a field that must be set before use."
                )
            continue  # an inherited field re-annotated: it keeps its inherited default
        value = cls.__dict__[key]
        if isinstance(value, Field):
            if value.default is MISSING and value.default_factory is MISSING:
                value.default_factory = _return_missing
        elif value is MISSING:
            setattr(cls, key, dataclasses.field(default_factory=_return_missing))
        elif not isinstance(value, _SHARED_TYPES):
            # lists, dicts, nested configs, tensors...: every instance gets its own copy
            setattr(cls, key, dataclasses.field(default_factory=functools.partial(copy.deepcopy, value)))
    cls.__annotations__ = annotations


def configclass(cls: type[T] | None = None, /, **kwargs: Any) -> type[T] | Callable[[type[T]], type[T]]:
    """Turn a class into a config class (a dataclass with Isaac Lab's conveniences).

    Use as ``@configclass`` or ``@configclass(frozen=True)``; keyword arguments go to
    :func:`dataclasses.dataclass`.

    Example::

        @configclass
        class RobotCfg:
            prim_path: str = MISSING
            stiffness = 10.0                    # no annotation needed
            joint_names = [".*"]                # copied per instance

        cfg = RobotCfg()                        # fine: validate() reports prim_path
        cfg = cfg.replace(prim_path="/World/envs/env_.*/Robot")
    """

    def wrap(cls: type[T]) -> type[T]:
        if not isinstance(cls, type):
            raise TypeError(f"@configclass decorates a class, got {type(cls).__name__}: {cls!r}.")
        _process_class(cls)
        for name, method in _METHODS.items():
            existing = getattr(cls, name, None)
            # a method the user wrote (here or in a base class) wins over ours
            if existing is None or any(existing is m for m in _METHODS.values()):
                setattr(cls, name, method)
        return dataclasses.dataclass(cls, **kwargs)

    return wrap if cls is None else wrap(cls)
