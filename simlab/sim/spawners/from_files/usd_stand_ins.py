"""simlab's stand-ins for the few Isaac Lab USD props that are plain shapes, so that ported configs
naming them by their Nucleus path spawn (and draw as markers) unchanged.

A stand-in is found by the USD file's name and built from the ``UsdFileCfg`` that names it: the same
scale, rigid-body, mass and collision properties, on a MuJoCo primitive of the prop's size.

    dex_cube_instanceable.usd   Isaac Lab's DexCube (in-hand and lift tasks): a 6 cm cube
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..shapes import ShapeCfg
    from .from_files_cfg import UsdFileCfg

DEX_CUBE_SIZE = 0.06
"""Edge length of Isaac Lab's unscaled DexCube [m]."""


def _dex_cube(cfg: UsdFileCfg) -> ShapeCfg:
    from ..shapes import CuboidCfg

    scale = cfg.scale or (1.0, 1.0, 1.0)
    return CuboidCfg(
        size=tuple(DEX_CUBE_SIZE * s for s in scale),
        rigid_props=cfg.rigid_props,
        mass_props=cfg.mass_props,
        collision_props=cfg.collision_props,
        visual_material=cfg.visual_material,
    )


STAND_INS: dict[str, Callable[[UsdFileCfg], ShapeCfg]] = {"dex_cube_instanceable.usd": _dex_cube}
"""USD file name -> the shape config that stands in for it."""


def stand_in(cfg: UsdFileCfg) -> ShapeCfg | None:
    """The shape standing in for the USD file ``cfg`` names, or None when simlab has none."""
    make = STAND_INS.get(os.path.basename(str(cfg.usd_path)))
    return make(cfg) if make is not None else None
