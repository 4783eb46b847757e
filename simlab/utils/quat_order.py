"""Which quaternion order a config holds: simlab reads (w, x, y, z); ``simlab.v3``'s configs say (x, y, z, w).

A config class written in another order than simlab's has the class attribute ``quat_order``
(``"xyzw"``). simlab's assets and sensors call :func:`refuse_other_order` on the config they are
built from, so such a config never reaches a reader of (w, x, y, z) unconverted.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from simlab.utils.errors import ConfigError

__all__ = ["refuse_other_order"]


def _other_order(value: Any, path: str, seen: set[int]) -> tuple[str, str] | None:
    """``(path, order)`` of the first config under ``value`` whose quaternions are not (w, x, y, z)."""
    order = getattr(type(value), "quat_order", "wxyz")
    if order != "wxyz":
        return path, order
    if id(value) in seen:
        return None
    seen.add(id(value))
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        children = ((f".{f.name}", getattr(value, f.name, None)) for f in dataclasses.fields(value))
    elif isinstance(value, dict):
        children = ((f"[{k!r}]", v) for k, v in value.items())
    elif isinstance(value, (list, tuple)):
        children = ((f"[{i}]", v) for i, v in enumerate(value))
    else:
        return None
    for name, child in children:
        found = _other_order(child, path + name, seen)
        if found:
            return found
    return None


def refuse_other_order(owner: str, cfg: Any, reader: str) -> None:
    """Raise a ConfigError if a config in ``cfg`` (any depth) holds quaternions in another order than
    simlab's (w, x, y, z), naming where (``owner`` and the path), which order and the ``reader``."""
    found = _other_order(cfg, owner, set())
    if found:
        where, order = found
        raise ConfigError(
            f"{where} is Isaac Lab 3.0's, rot in ({', '.join(order)}) order, but simlab's 2.x {reader} reads "
            "(w, x, y, z): build it with simlab.v3 (its assets, sensors, scene or env), which converts it."
        )
