"""Rays against static geoms on MuJoCo Warp, each tested only against the geoms of its xy bin.

``mujoco_warp.rays`` tests every ray against every geom of its model: for a height scanner over a
generated terrain (200 height-field tiles) that is 200 geom tests per ray, most of them two box tests
that miss. A vertical ray can only hit the geoms over its own xy point (``XyBins``), so this kernel
tests it against those of its cell alone, with MuJoCo Warp's own per-geom functions (``ray_hfield``,
``ray_geom``): the same distances as ``mujoco_warp.rays``. Rays that are not vertical or lie within a
hair of a cell's edge are tested against all the targets; vertical rays off the bins against the
unbounded ones (planes).
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np
import warp as wp
from mujoco_warp._src.ray import ray_geom, ray_hfield
from mujoco_warp._src.types import GeomType

from .ray_targets import XyBins, geom_xy_bounds

_MAXVAL = 1.0e10  # MuJoCo's mjMAXVAL: no hit yet
_EDGE = 1.0e-4  # rays this close to a cell's edge (a fraction of the cell) are tested against all geoms


@wp.kernel
def _binned_rays(
    geom_type: wp.array(dtype=int),
    geom_dataid: wp.array2d(dtype=int),
    geom_size: wp.array(dtype=wp.vec3),
    geom_pos: wp.array(dtype=wp.vec3),
    geom_mat: wp.array(dtype=wp.mat33),
    hfield_size: wp.array(dtype=wp.vec4),
    hfield_nrow: wp.array(dtype=int),
    hfield_ncol: wp.array(dtype=int),
    hfield_adr: wp.array(dtype=int),
    hfield_data: wp.array(dtype=float),
    bin_origin: wp.vec2,
    bin_size: float,
    bin_rows: int,
    bin_cols: int,
    cell_start: wp.array(dtype=int),
    cell_geoms: wp.array(dtype=int),
    pnt: wp.array(dtype=wp.vec3),
    vec: wp.array(dtype=wp.vec3),
    dist_out: wp.array(dtype=float),
    normal_out: wp.array(dtype=wp.vec3),
):
    ray = wp.tid()
    p = pnt[ray]
    v = vec[ray]
    cell = bin_rows * bin_cols  # after the cells' lists: all the targets, then the unbounded ones
    if v[0] == 0.0 and v[1] == 0.0:
        x = (p[0] - bin_origin[0]) / bin_size
        y = (p[1] - bin_origin[1]) / bin_size
        i = wp.floor(x)
        j = wp.floor(y)
        near_edge = wp.min(wp.min(x - i, 1.0 - (x - i)), wp.min(y - j, 1.0 - (y - j))) < _EDGE
        inside = i >= 0.0 and j >= 0.0 and i < float(bin_rows) and j < float(bin_cols)
        if inside and not near_edge:
            cell = int(i) * bin_cols + int(j)
        elif x < -_EDGE or y < -_EDGE or x > float(bin_rows) + _EDGE or y > float(bin_cols) + _EDGE:
            cell = bin_rows * bin_cols + 1  # off the bins: only an unbounded geom (a plane) lies there
    best = float(_MAXVAL)
    best_normal = wp.vec3()
    for k in range(cell_start[cell], cell_start[cell + 1]):
        g = cell_geoms[k]
        if geom_type[g] == int(GeomType.HFIELD):
            d, n = ray_hfield(
                geom_dataid, hfield_size, hfield_nrow, hfield_ncol, hfield_adr, hfield_data,
                geom_pos[g], geom_mat[g], p, v, g, 0,
            )  # fmt: skip
        else:
            d, n = ray_geom(geom_pos[g], geom_mat[g], geom_size[g], p, v, geom_type[g])
        if d >= 0.0 and d < best:
            best = d
            best_normal = n
    if best >= _MAXVAL:
        dist_out[ray] = -1.0
    else:
        dist_out[ray] = best
    normal_out[ray] = best_normal


class BinnedRays:
    """The target model's geoms and bins on ``device``; :meth:`launch` casts rays given as Warp arrays."""

    def __init__(self, model: mujoco.MjModel, bins: XyBins, device: str):
        data = mujoco.MjData(model)
        mujoco.mj_kinematics(model, data)
        # each cell's geoms (its bin's), then all the targets, then those that extend without bound
        per_cell = [bins.geoms[b] if b >= 0 else () for b in bins.table.tolist()]
        per_cell += [tuple(range(model.ngeom)), tuple(np.flatnonzero(~np.isfinite(geom_xy_bounds(model)).all(axis=1)))]
        start = np.cumsum([0] + [len(ids) for ids in per_cell])
        flat = [g for ids in per_cell for g in ids]
        with wp.ScopedDevice(wp.get_device(device)):
            self._inputs = [
                wp.array(model.geom_type.astype(np.int32), dtype=int),
                wp.array(model.geom_dataid.astype(np.int32).reshape(1, -1), dtype=int),
                wp.array(model.geom_size.astype(np.float32), dtype=wp.vec3),
                wp.array(data.geom_xpos.astype(np.float32), dtype=wp.vec3),
                wp.array(data.geom_xmat.astype(np.float32).reshape(-1, 3, 3), dtype=wp.mat33),
                wp.array(model.hfield_size.astype(np.float32).reshape(-1, 4), dtype=wp.vec4),
                wp.array(model.hfield_nrow.astype(np.int32), dtype=int),
                wp.array(model.hfield_ncol.astype(np.int32), dtype=int),
                wp.array(model.hfield_adr.astype(np.int32), dtype=int),
                wp.array(model.hfield_data.astype(np.float32), dtype=float),
                wp.vec2(*bins.origin.tolist()),
                float(bins.size),
                int(bins.counts[0]),
                int(bins.counts[1]),
                wp.array(start.astype(np.int32), dtype=int),
                wp.array(np.asarray(flat, dtype=np.int32), dtype=int),
            ]
        self.device = device

    def launch(self, pnt: Any, vec: Any, dist: Any, normal: Any) -> None:
        """(n,) vec3 starts and unit directions -> (n,) distances (-1: no hit) and vec3 normals."""
        wp.launch(_binned_rays, dim=pnt.shape[0], inputs=[*self._inputs, pnt, vec, dist, normal], device=self.device)
