"""Flat patches: points on a tile where a robot (or a goal) can be placed on level ground.

Isaac Lab's rule, by rejection sampling: a candidate centre is drawn uniformly within ``x_range`` x
``y_range`` around the tile's origin; the ground height is read at 10 points on a ring ``patch_radius``
away (one ring per radius) and, here, at the centre too; the candidate is kept when every one of those
heights lies within ``z_range`` of the origin's height and they differ by at most ``max_height_diff``.
As in Isaac Lab, only those points are read: a narrow step between two ring points, or a bump inside
the ring, is not seen (use more radii to look inside).
simlab reads the heights from the tile's surface itself (the height field in the model, or the boxes'
tops), not by ray casting a mesh. The patches are returned in the world frame, the frame the terms that
use them (a reset onto the terrain, a goal on the terrain) place things in.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import MISSING

import numpy as np

from simlab.utils import configclass

RING_POINTS = 10
"""Height samples on each ring around a candidate centre (Isaac Lab's count)."""
CANDIDATES_PER_ROUND = 256
MAX_ROUNDS = 200
"""At most ``MAX_ROUNDS * CANDIDATES_PER_ROUND`` candidates are tried per tile before giving up."""


@configclass
class FlatPatchSamplingCfg:
    """Where and how to look for flat patches on a sub-terrain (Isaac Lab's fields)."""

    num_patches: int = MISSING
    """How many patches to find on each tile."""
    patch_radius: float | list[float] = MISSING
    """Radius of the patch [m]; with a list, the ground must be flat on every ring."""
    x_range: tuple[float, float] = (-1e6, 1e6)
    """Where the patch centre may lie along x, relative to the tile's origin [m] (clipped to the tile)."""
    y_range: tuple[float, float] = (-1e6, 1e6)
    """Where the patch centre may lie along y, relative to the tile's origin [m] (clipped to the tile)."""
    z_range: tuple[float, float] = (-1e6, 1e6)
    """Heights the patch may have, relative to the tile origin's height [m]."""
    max_height_diff: float = MISSING
    """Largest difference between the highest and lowest point of a patch [m]."""


HeightFunction = Callable[[np.ndarray, np.ndarray], np.ndarray]
"""Ground height [m] at tile-frame points x, y (arrays of one shape)."""


def find_flat_patches(
    height_at: HeightFunction,
    tile_size: tuple[float, float],
    origin: np.ndarray,
    cfg: FlatPatchSamplingCfg,
    rng: np.random.Generator,
    where: str = "sub-terrain",
) -> np.ndarray:
    """(num_patches, 3) centres of flat patches in the tile frame (x, y in [0, size], z the ground height).

    ``where`` names the tile in errors. Raises a ValueError when the config is invalid or when the tile
    has no such patch (then the ranges, radius or height tolerance must be loosened).
    """
    check_cfg(cfg, where)
    radii = np.atleast_1d(np.asarray(cfg.patch_radius, dtype=np.float64))
    reach = float(radii.max())
    # the centre's range, around the origin and clipped so the whole ring stays on the tile
    low_x, high_x = max(origin[0] + cfg.x_range[0], reach), min(origin[0] + cfg.x_range[1], tile_size[0] - reach)
    low_y, high_y = max(origin[1] + cfg.y_range[0], reach), min(origin[1] + cfg.y_range[1], tile_size[1] - reach)
    if low_x > high_x or low_y > high_y:
        raise ValueError(
            f"{where}: no room for a flat patch of radius {reach} m within x_range={cfg.x_range},"
            f" y_range={cfg.y_range} of the tile origin on a {tuple(tile_size)} m tile; shrink patch_radius or"
            " widen the ranges"
        )
    low_z, high_z = origin[2] + cfg.z_range[0], origin[2] + cfg.z_range[1]
    angles = np.linspace(0.0, 2 * np.pi, RING_POINTS, endpoint=False)
    ring = np.concatenate([np.zeros((1, 2)), *(r * np.stack([np.cos(angles), np.sin(angles)], -1) for r in radii)])

    found: list[np.ndarray] = []
    for _ in range(MAX_ROUNDS):
        centres = np.stack(
            [rng.uniform(low_x, high_x, CANDIDATES_PER_ROUND), rng.uniform(low_y, high_y, CANDIDATES_PER_ROUND)], -1
        )
        points = centres[:, None, :] + ring[None]  # (candidates, points, 2); point 0 is the centre
        heights = height_at(points[..., 0], points[..., 1])
        flat = heights.max(axis=1) - heights.min(axis=1) <= cfg.max_height_diff
        in_range = ((heights >= low_z) & (heights <= high_z)).all(axis=1)
        good = flat & in_range
        found.extend(np.concatenate([centres[good], heights[good, :1]], axis=1))
        if len(found) >= cfg.num_patches:
            return np.stack(found[: cfg.num_patches])
    raise ValueError(
        f"{where}: found {len(found)} of {cfg.num_patches} flat patches (radius {cfg.patch_radius} m, height"
        f" difference <= {cfg.max_height_diff} m, z_range={cfg.z_range} of the origin) in"
        f" {MAX_ROUNDS * CANDIDATES_PER_ROUND} tries; loosen max_height_diff or z_range, shrink patch_radius,"
        " or sample a flatter sub-terrain"
    )


def check_cfg(cfg: FlatPatchSamplingCfg, where: str) -> None:
    """Raise a ValueError naming the field of ``cfg`` that cannot work."""
    if not isinstance(cfg, FlatPatchSamplingCfg):
        raise ValueError(f"{where}: flat_patch_sampling values must be FlatPatchSamplingCfg, got {type(cfg).__name__}")
    cfg.validate()
    if int(cfg.num_patches) < 1:
        raise ValueError(f"{where}: FlatPatchSamplingCfg.num_patches must be >= 1, got {cfg.num_patches}")
    radii = np.atleast_1d(np.asarray(cfg.patch_radius, dtype=np.float64))
    if radii.size == 0 or (radii < 0).any():
        raise ValueError(f"{where}: FlatPatchSamplingCfg.patch_radius must be >= 0 [m], got {cfg.patch_radius}")
    if cfg.max_height_diff < 0:
        raise ValueError(f"{where}: FlatPatchSamplingCfg.max_height_diff must be >= 0 [m], got {cfg.max_height_diff}")
    for name in ("x_range", "y_range", "z_range"):
        low, high = getattr(cfg, name)
        if low > high:
            raise ValueError(
                f"{where}: FlatPatchSamplingCfg.{name} must be (low, high) with low <= high, got {(low, high)}"
            )
