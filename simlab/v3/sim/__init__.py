"""``isaaclab.sim`` of Isaac Lab 3.0: simlab's simulation and spawners, orientations in (x, y, z, w).

Isaac Lab 3.0 code spawns with ``cfg.func(prim_path, cfg, translation=..., orientation=(x, y, z, w))``
and ``create_prim(..., orientation=...)``. Here every spawner config class of :mod:`simlab.sim` is a
subclass whose ``func`` reads ``orientation`` in (x, y, z, w) (checked as a ``rot`` of a 3.0 config is,
:func:`simlab.v3._order.check_xyzw_rot`) and calls simlab's spawner with (w, x, y, z); so are the
``spawn_*`` functions and ``create_prim``. Such a config carries ``quat_order = "xyzw"``: a scene or env
of :mod:`simlab.v3` turns it back into simlab's class (its ``func`` simlab's own) before spawning, and
simlab's 2.x assets refuse it. Every other name is :mod:`simlab.sim`'s.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable
from typing import Any, ClassVar

import simlab.sim as _sim
from simlab.utils import configclass
from simlab.v3._order import check_xyzw_rot, to_simlab

__all__ = ["create_prim", "xyzw_spawner"]


def _wxyz(owner: str, orientation: Any) -> tuple[float, ...] | None:
    if orientation is None:
        return None
    check_xyzw_rot(owner, orientation)
    x, y, z, w = (float(v) for v in orientation)
    return (w, x, y, z)


def xyzw_spawner(func: Callable) -> Callable:
    """``func`` (a simlab spawner, orientation (w, x, y, z)) taking Isaac Lab 3.0's (x, y, z, w)."""

    @functools.wraps(func)
    def spawn(prim_path: str, cfg: Any, translation: Any = None, orientation: Any = None, **kwargs: Any) -> Any:
        owner = f"{func.__name__}('{prim_path}', orientation=...)"
        return func(prim_path, to_simlab(cfg), translation=translation, orientation=_wxyz(owner, orientation), **kwargs)

    spawn.simlab_func = func
    return spawn


@functools.wraps(_sim.create_prim)
def create_prim(prim_path: str, prim_type: str = "Xform", *args: Any, orientation: Any = None, **kwargs: Any) -> str:
    owner = f"create_prim('{prim_path}', orientation=...)"
    return _sim.create_prim(prim_path, prim_type, *args, orientation=_wxyz(owner, orientation), **kwargs)


@functools.cache
def _spawner_class(base: type) -> type:
    """``base`` (a spawner config of simlab) whose default ``func`` reads orientations in (x, y, z, w)."""
    default = next(f for f in dataclasses.fields(base) if f.name == "func").default

    @configclass
    class Xyzw(base):
        quat_order: ClassVar[str] = "xyzw"
        simlab_class: ClassVar[type] = base
        func: Callable = xyzw_spawner(default) if callable(default) else default

    Xyzw.__name__, Xyzw.__qualname__, Xyzw.__module__ = base.__name__, base.__qualname__, __name__
    return Xyzw


_RENAMED = {
    "CollisionBaseCfg": "CollisionPropertiesCfg",
    "UsdPhysicsCollisionCfg": "CollisionPropertiesCfg",
    "UsdPhysicsRigidBodyCfg": "RigidBodyPropertiesCfg",
    "MassCfg": "MassPropertiesCfg",
}
"""Isaac Lab 3.0's schema config names -> 2.x's (simlab's): 3.0 split each schema into per-backend
configs; the fields of these (``collision_enabled``; ``rigid_body_enabled``, ``kinematic_enabled``;
``mass``, ``density``) are 2.x's config's own."""


def __getattr__(name: str) -> Any:
    value = getattr(_sim, _RENAMED.get(name, name))
    if isinstance(value, type) and dataclasses.is_dataclass(value):
        if any(f.name == "func" for f in dataclasses.fields(value)):
            return _spawner_class(value)
    elif name.startswith("spawn_") and callable(value):
        return xyzw_spawner(value)
    return value
