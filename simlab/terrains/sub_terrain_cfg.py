"""The base config of a sub-terrain (one tile of the terrain grid) and the geometry it produces.

A sub-terrain function takes a difficulty in [0, 1], its config and a random generator, and returns
a :class:`TileGeometry`: a height field over the tile and/or axis-aligned boxes, both in the tile's
frame (x in [0, size[0]], y in [0, size[1]], ground level z = 0), and the point where a robot starts.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import MISSING, dataclass, field

import numpy as np

from simlab.utils import configclass


@dataclass
class TileGeometry:
    """What one sub-terrain is made of, in the tile frame."""

    origin: np.ndarray
    """(3,) where an env on this tile starts: the tile centre, at the ground's height there [m]."""
    heights: np.ndarray | None = None
    """(nx, ny) heights [m] sampled every ``horizontal_scale`` over the whole tile, indexed [x, y]."""
    boxes: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)
    """(centre (3,), full size (3,)) of each box [m]."""


@configclass
class SubTerrainBaseCfg:
    """One kind of tile; the generator fills ``size`` with its own tile size."""

    function: Callable[[float, SubTerrainBaseCfg, np.random.Generator], TileGeometry] = MISSING
    proportion: float = 1.0
    """Share of the terrain's columns (curriculum) or tiles (random) of this kind (normalised)."""
    size: tuple[float, float] = (10.0, 10.0)
    """Tile size along x and y [m]; set by the terrain generator."""
    flat_patch_sampling: dict | None = None
    """Name -> :class:`~simlab.terrains.FlatPatchSamplingCfg`: flat spots to find on each tile of this
    kind (the generator's ``flat_patches[name]``); None: none."""


def difficulty_lerp(value_range: tuple[float, float], difficulty: float) -> float:
    """The value ``difficulty`` of the way from ``value_range[0]`` to ``value_range[1]``."""
    return value_range[0] + difficulty * (value_range[1] - value_range[0])
