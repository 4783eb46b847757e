"""The static geometry rays are cast against, as a MuJoCo model of its own.

Isaac Lab's ray caster casts against static meshes named by ``mesh_prim_paths``. simlab copies the
geoms those paths name (static geoms of the world body: the terrain's height fields and boxes, a
ground plane) into a small MuJoCo model that holds nothing else, so a ray never hits the robot
carrying the sensor, and casting costs only the target geoms. Every MuJoCo world holds the same
static geometry in its own frame (a generated terrain is shared; a ground plane sits at the same
place in every world), so one copy serves all envs: rays go in in each world's frame.

Casting uses MuJoCo's own ray functions: ``mj_ray`` on the CPU (``mjbatch.Batch.rays``, on its
thread pool), ``mujoco_warp.rays`` on the GPU. Both return the distance along each ray to the
first surface, -1 where the ray hits nothing, and on request the surface's unit normal there.
"""

from __future__ import annotations

import re
from typing import Any

import mujoco
import numpy as np
import torch

from simlab.sensors.sensor_base import prim_path_in_model


def find_target_geoms(model: mujoco.MjModel, mesh_prim_paths: list[str], owner: str) -> list[int]:
    """Ids of the geoms the paths name: ``/World/ground`` names the geom ``ground`` and every geom
    ``ground/...`` (a terrain's tiles); a path may be a regex. They must be static (world body)."""
    if not mesh_prim_paths:
        raise ValueError(
            f"{owner}.mesh_prim_paths is empty: name the geometry to cast against, e.g. ['/World/ground']"
            " (the scene's terrain)"
        )
    names = [model.geom(g).name for g in range(model.ngeom)]
    ids: list[int] = []
    for path in mesh_prim_paths:
        entity = prim_path_in_model(path)
        pattern = re.compile(f"{entity}(/.*)?")
        matched = [g for g, name in enumerate(names) if name and pattern.fullmatch(name)]
        if not matched:
            static = sorted({n.split("/")[0] for g, n in enumerate(names) if n and _is_static(model, g)})
            raise ValueError(
                f"{owner}.mesh_prim_paths entry '{path}' names no geom of the model; static geometry there:"
                f" {['/World/' + s for s in static]}"
            )
        moving = [names[g] for g in matched if not _is_static(model, g)]
        if moving:
            raise ValueError(
                f"{owner}.mesh_prim_paths entry '{path}' names geoms of moving bodies {moving[:5]}; the ray"
                " caster casts against static geometry only (as Isaac Lab's RayCaster): name the terrain"
                " or other fixed geometry"
            )
        ids += [g for g in matched if g not in ids]
    return ids


def _is_static(model: mujoco.MjModel, geom: int) -> bool:
    return model.body_weldid[model.geom_bodyid[geom]] == 0


def target_model(model: mujoco.MjModel, geom_ids: list[int]) -> mujoco.MjModel:
    """A model holding only the geoms ``geom_ids`` of ``model`` (static, at their world poses)."""
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    spec = mujoco.MjSpec()
    spec.modelname = "simlab_ray_targets"
    for g in geom_ids:
        geom_type = int(model.geom_type[g])
        if geom_type == mujoco.mjtGeom.mjGEOM_MESH:
            raise ValueError(
                f"ray caster target geom '{model.geom(g).name}' is a mesh; simlab casts against planes,"
                " height fields and primitive shapes"
            )
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, data.geom_xmat[g])
        geom = spec.worldbody.add_geom(
            name=model.geom(g).name,
            type=mujoco.mjtGeom(geom_type),
            size=model.geom_size[g].tolist(),
            pos=data.geom_xpos[g].tolist(),
            quat=quat.tolist(),
            rgba=[1.0, 1.0, 1.0, 1.0],  # mj_ray skips invisible geoms
        )
        if geom_type == mujoco.mjtGeom.mjGEOM_HFIELD:
            h = model.geom_dataid[g]
            nrow, ncol, adr = int(model.hfield_nrow[h]), int(model.hfield_ncol[h]), int(model.hfield_adr[h])
            name = f"hfield_{g}"
            spec.add_hfield(
                name=name,
                size=model.hfield_size[h].tolist(),
                nrow=nrow,
                ncol=ncol,
                userdata=model.hfield_data[adr : adr + nrow * ncol].tolist(),
            )
            geom.hfieldname = name
    return spec.compile()


class RayTargets:
    """Casts ``num_rays`` rays (a fixed count) against the target model, on the simulation's backend."""

    def __init__(self, model: mujoco.MjModel, num_rays: int, physics: Any, device: str):
        self.model = model
        self.num_rays = num_rays
        self.device = torch.device(device)
        if self.device.type == "cpu":
            self._caster = _MujocoCaster(model, num_rays, getattr(physics, "num_threads", 1))
        else:
            self._caster = _WarpCaster(model, num_rays, physics, device)

    def cast(self, starts: torch.Tensor, directions: torch.Tensor) -> torch.Tensor:
        """(num_rays,) distance along each unit direction to the first hit; -1 where none."""
        return self._caster.cast(starts.reshape(-1, 3), directions.reshape(-1, 3))

    def cast_with_normals(self, starts: torch.Tensor, directions: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """The distances of :meth:`cast` and the (num_rays, 3) unit surface normals at the hits
        (zero where a ray hits nothing)."""
        return self._caster.cast(starts.reshape(-1, 3), directions.reshape(-1, 3), with_normals=True)


def _mjbatch_rays(batch: Any, starts: torch.Tensor, directions: torch.Tensor, with_normals: bool = False) -> Any:
    """``mj_ray`` for each ray on ``batch``'s copies of one model (the rays split evenly over them):
    the distances, and with ``with_normals`` the (n, 3) surface normals too."""
    n, copies = len(starts), batch.num_sims
    per_copy = -(-n // copies)
    pnt = np.zeros((copies * per_copy, 3), np.float32)
    vec = np.zeros((copies * per_copy, 3), np.float32)
    vec[n:, 2] = -1.0  # padding rays: any valid direction
    pnt[:n], vec[:n] = starts.numpy(), directions.numpy()
    dist = np.zeros((copies, per_copy), np.float32)
    normal = np.zeros((copies, per_copy, 3), np.float32) if with_normals else None
    batch.rays(pnt.reshape(copies, per_copy, 3), vec.reshape(copies, per_copy, 3), dist, normal=normal)
    distance = torch.from_numpy(dist.reshape(-1)[:n])
    return (distance, torch.from_numpy(normal.reshape(-1, 3)[:n])) if with_normals else distance


def _static_batch(model: mujoco.MjModel, copies: int) -> Any:
    import mjbatch

    batch = mjbatch.Batch(model, copies, num_threads=copies, forward=False)
    batch.forward()  # places the static geoms (geom_xpos, geom_xmat)
    return batch


def geom_xy_bounds(model: mujoco.MjModel) -> np.ndarray:
    """(ngeom, 4) world-frame xy bounds (x min, y min, x max, y max) of each geom; infinite planes
    span everything."""
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    xmat = data.geom_xmat.reshape(-1, 3, 3)
    centre = data.geom_xpos + np.einsum("gij,gj->gi", xmat, model.geom_aabb[:, :3])
    half = np.einsum("gij,gj->gi", np.abs(xmat), model.geom_aabb[:, 3:])
    bounds = np.concatenate([centre[:, :2] - half[:, :2], centre[:, :2] + half[:, :2]], axis=1)
    planes = model.geom_type == mujoco.mjtGeom.mjGEOM_PLANE
    infinite = planes & ((model.geom_size[:, 0] <= 0) | (model.geom_size[:, 1] <= 0))
    bounds[infinite] = [-np.inf, -np.inf, np.inf, np.inf]
    return bounds


class XyBins:
    """Square bins on the xy plane, each naming the target geoms that overlap it (a terrain's tiles: one
    height field or a few boxes per bin). A ray pointing straight up or down (a height scanner's, in
    "yaw" or "world" alignment) can only hit geoms over its own xy point, so it need only be tested
    against its bin's geoms. ``geoms`` lists each bin's geom ids, ``table`` each cell's bin (-1: none
    overlaps it); ``empty`` when the targets are too few for bins to gain anything."""

    MAX_BINS = 1024
    MIN_GEOMS = 16  # fewer targets: binning gains nothing

    def __init__(self, model: mujoco.MjModel):
        self.geoms: list[tuple[int, ...]] = []
        bounds = geom_xy_bounds(model)
        finite = np.isfinite(bounds).all(axis=1)
        if finite.sum() < self.MIN_GEOMS:
            return
        lo, hi = bounds[finite, :2], bounds[finite, 2:]
        size = float(np.median((hi - lo).max(axis=1)))
        offset = np.median(lo, axis=0) % size  # bin edges on the typical geom's edges (a tile's)
        while True:
            origin = np.floor((lo.min(axis=0) - offset) / size) * size + offset
            counts = np.ceil((hi.max(axis=0) - origin) / size).astype(int)
            if counts.prod() <= self.MAX_BINS:
                break
            size *= 1.5
        self.tol = 1e-6 * size
        models: dict[tuple[int, ...], int] = {}
        table = np.full(counts.prod(), -1, dtype=np.int64)
        for i in range(counts[0]):
            for j in range(counts[1]):
                bin_lo = origin + size * np.array([i, j])
                bin_hi = bin_lo + size
                inside = (bounds[:, 2] > bin_lo[0] + self.tol) & (bounds[:, 0] < bin_hi[0] - self.tol)
                inside &= (bounds[:, 3] > bin_lo[1] + self.tol) & (bounds[:, 1] < bin_hi[1] - self.tol)
                ids = tuple(np.flatnonzero(inside).tolist())
                if ids and ids not in models:
                    models[ids] = len(self.geoms)
                    self.geoms.append(ids)
                table[i * counts[1] + j] = models.get(ids, -1)
        self.origin, self.size, self.counts, self.table = origin, size, counts, table

    @property
    def empty(self) -> bool:
        return not self.geoms


class _MujocoCaster:
    """``mj_ray`` on mjbatch's thread pool, testing each ray only against the geoms near it.

    ``mj_ray`` tests a ray against every geom of its model (about 60 ns each, ~0.5 us for a height
    field the ray comes near), so each of the :class:`XyBins` gets a small model of its own geoms; a
    vertical ray is cast in its bin's model alone, any other ray against all the targets.
    """

    def __init__(self, model: mujoco.MjModel, num_rays: int, num_threads: int):
        copies = max(1, min(num_threads, num_rays))  # one per thread: the rays are split over them
        self.full = _static_batch(model, copies)
        bins = XyBins(model)
        self.bins: list[Any] = [_static_batch(target_model(model, list(ids)), copies) for ids in bins.geoms]
        if bins.empty:
            return
        self.origin, self.size, self.counts = torch.tensor(bins.origin), bins.size, torch.tensor(bins.counts)
        self.table = torch.from_numpy(bins.table)

    def cast(self, starts: torch.Tensor, directions: torch.Tensor, with_normals: bool = False) -> Any:
        if not self.bins:
            return _mjbatch_rays(self.full, starts, directions, with_normals)
        distance = torch.full((len(starts),), -1.0)
        normal = torch.zeros(len(starts), 3)
        cell = torch.floor((starts[:, :2].double() - self.origin) / self.size).long()
        inside = ((cell >= 0) & (cell < self.counts)).all(dim=1)
        vertical = (directions[:, :2] == 0).all(dim=1)
        binned = inside & vertical
        others = (~binned).nonzero().flatten()
        if len(others):
            cast = _mjbatch_rays(self.full, starts[others], directions[others], with_normals)
            distance[others], normal[others] = cast if with_normals else (cast, 0.0)
        index = torch.where(binned, cell[:, 0] * self.counts[1] + cell[:, 1], 0)
        ray_bin = torch.where(binned, self.table[index], -1)
        order = torch.argsort(ray_bin)
        bins, counts = torch.unique_consecutive(ray_bin[order], return_counts=True)
        for b, rays in zip(bins.tolist(), torch.split(order, counts.tolist()), strict=True):
            if b >= 0:  # -1: not binned (done above) or a bin without geoms (a miss)
                cast = _mjbatch_rays(self.bins[b], starts[rays], directions[rays], with_normals)
                distance[rays], normal[rays] = cast if with_normals else (cast, 0.0)
        return (distance, normal) if with_normals else distance


class _WarpCaster:
    """All rays in one launch, recorded into the env step's CUDA graph like the physics (through the
    backend's ``run_warp``): with :class:`XyBins`, each vertical ray tested against its bin's geoms
    (``warp_binned_rays``), else ``mujoco_warp.rays`` over one world of the target model."""

    def __init__(self, model: mujoco.MjModel, num_rays: int, physics: Any, device: str, binned: bool = True):
        from simlab.sim.backends.cuda import require_cuda_backend

        wp, mjw = require_cuda_backend(device)
        vec6 = wp.types.vector(length=6, dtype=wp.float32)  # mujoco_warp's geom-group type (public warp)

        self._wp, self._mjw, self._physics = wp, mjw, physics
        data = mujoco.MjData(model)
        mujoco.mj_forward(model, data)  # static geom poses, copied by put_data
        with wp.ScopedDevice(wp.get_device(device)):
            self._m = mjw.put_model(model)
            self._d = mjw.put_data(model, data, nworld=1, nconmax=0, njmax=0)
            self._bodyexclude = wp.full(num_rays, -1, dtype=int)
        wp.synchronize_device(wp.get_device(device))
        self._pnt = torch.zeros(1, num_rays, 3, device=device)
        self._vec = torch.zeros(1, num_rays, 3, device=device)
        self._dist = torch.zeros(1, num_rays, device=device)
        self._geomid = torch.zeros(1, num_rays, dtype=torch.int32, device=device)
        self._normal = torch.zeros(1, num_rays, 3, device=device)
        self._args = (
            wp.from_torch(self._pnt, dtype=wp.vec3),
            wp.from_torch(self._vec, dtype=wp.vec3),
            vec6(-1, -1, -1, -1, -1, -1),  # every geom group
            True,  # the targets are static geoms
            self._bodyexclude,
            wp.from_torch(self._dist),
            wp.from_torch(self._geomid),
            wp.from_torch(self._normal, dtype=wp.vec3),
        )
        self._key = ("simlab_rays", id(self))
        bins = XyBins(model)
        self._binned = None
        if binned and not bins.empty:
            from .warp_binned_rays import BinnedRays

            self._binned = BinnedRays(model, bins, device)
            self._binned_args = [wp.from_torch(t[0], dtype=wp.vec3) for t in (self._pnt, self._vec)]
            self._binned_args += [wp.from_torch(self._dist[0]), wp.from_torch(self._normal[0], dtype=wp.vec3)]

    def cast(self, starts: torch.Tensor, directions: torch.Tensor, with_normals: bool = False) -> Any:
        self._pnt[0].copy_(starts)
        self._vec[0].copy_(directions)
        if self._binned is not None:
            self._physics.run_warp(self._key, lambda: self._binned.launch(*self._binned_args))
        else:
            self._physics.run_warp(self._key, lambda: self._mjw.rays(self._m, self._d, *self._args))
        return (self._dist[0], self._normal[0]) if with_normals else self._dist[0]
