"""Which quaternion order a config is written in, and the conversion of Isaac Lab 3.0's configs to simlab's.

The order is a property of a config's *class*: simlab's classes (``simlab.assets``) hold ``rot`` in
``(w, x, y, z)``, the classes of ``simlab.v3`` in ``(x, y, z, w)`` (their ``quat_order`` says so). So
both kinds can sit in one config tree and in one process without a guess. simlab's assets and
scenes read ``(w, x, y, z)``; :func:`to_simlab` turns every ``(x, y, z, w)`` config of a tree into its
simlab class with the components reordered, once (the result has no 3.0 config left, so converting
again changes nothing), and simlab's assets refuse a 3.0 config that reached them unconverted.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, ClassVar

from simlab.utils import configclass
from simlab.utils.errors import ConfigError

__all__ = ["check_xyzw_rot", "replace_fields", "to_simlab", "xyzw_class"]


def check_xyzw_rot(owner: str, rot: Any) -> None:
    """Refuse a ``rot`` of a 3.0 config that cannot be an (x, y, z, w) quaternion meant as written:
    four numbers of unit norm, and not (1, 0, 0, 0), Isaac Lab 2.x's identity (in (x, y, z, w) order a
    half turn about x, which a default pose is not)."""
    values = [float(v) for v in rot]
    if len(values) != 4 or not math.isclose(math.fsum(v * v for v in values), 1.0, rel_tol=1e-3):
        raise ConfigError(
            f"{owner} rot={tuple(rot)} is not a unit quaternion; Isaac Lab 3.0 configs take (x, y, z, w)."
        )
    if values == [1.0, 0.0, 0.0, 0.0]:
        raise ConfigError(
            f"{owner} rot=(1, 0, 0, 0) is Isaac Lab 2.x's identity in (w, x, y, z) order; this Isaac Lab 3.0 config "
            "takes (x, y, z, w), whose identity is (0, 0, 0, 1). For a half turn about x write (-1, 0, 0, 0)."
        )


def xyzw_class(base: type, module: str) -> type:
    """``base`` (a simlab config with a ``rot`` field: an initial state, a sensor offset) holding ``rot``
    in (x, y, z, w) order, identity ``(0, 0, 0, 1)``, checked when made (:func:`check_xyzw_rot`)."""
    owner = base.__qualname__

    @configclass
    class Xyzw(base):
        quat_order: ClassVar[str] = "xyzw"
        simlab_class: ClassVar[type] = base
        rot: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 1.0)
        """Quaternion (x, y, z, w), Isaac Lab 3.0's order."""

        def __post_init__(self) -> None:
            check_xyzw_rot(owner, self.rot)

    Xyzw.__name__ = base.__name__
    Xyzw.__qualname__ = base.__qualname__
    Xyzw.__module__ = module
    return Xyzw


def _simlab_copy(cfg: Any) -> Any:
    """The simlab (w, x, y, z) class's instance of a 3.0 config: the same fields, ``rot`` reordered and a
    spawner's ``func`` simlab's own (:mod:`simlab.v3.sim`, whose spawn functions read (x, y, z, w))."""
    base = type(cfg).simlab_class
    values = {f.name: to_simlab(getattr(cfg, f.name)) for f in dataclasses.fields(cfg) if f.init}
    if "rot" in values:
        x, y, z, w = values["rot"]
        values["rot"] = (w, x, y, z)
    if "func" in values:
        values["func"] = getattr(values["func"], "simlab_func", values["func"])
    return base(**values)


def replace_fields(cfg: Any, **changes: Any) -> Any:
    """A shallow copy of config ``cfg`` with ``changes`` set, without running ``__post_init__`` again
    (the config was made already; running it twice would apply its edits twice)."""
    copy = type(cfg).__new__(type(cfg))
    copy.__dict__.update(cfg.__dict__)
    copy.__dict__.update(changes)
    return copy


def to_simlab(value: Any) -> Any:
    """``value`` with every (x, y, z, w) config in it (any depth: config fields, dicts, lists, tuples) as
    simlab's (w, x, y, z) config; what holds none is returned as it is (not copied)."""
    if getattr(type(value), "quat_order", "wxyz") == "xyzw":
        return _simlab_copy(value)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        changed = {}
        for f in dataclasses.fields(value):
            old = getattr(value, f.name)
            new = to_simlab(old)
            if new is not old:
                changed[f.name] = new
        return replace_fields(value, **changed) if changed else value
    if isinstance(value, dict):
        items = {k: to_simlab(v) for k, v in value.items()}
        return items if any(items[k] is not value[k] for k in value) else value
    if isinstance(value, (list, tuple)) and not isinstance(value, str):
        items = [to_simlab(v) for v in value]
        if all(a is b for a, b in zip(items, value)):
            return value
        return type(value)(items) if isinstance(value, list) else tuple(items)
    return value
