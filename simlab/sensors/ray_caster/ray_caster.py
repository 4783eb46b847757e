"""The ray caster: rays from a body against static geometry (Isaac Lab's height scanner).

Rays are laid out by the pattern in the sensor's frame (the body's frame moved by ``offset``),
turned with the body as ``ray_alignment`` says, and cast with MuJoCo's ray functions against a
copy of the target geoms alone (``ray_targets``), so the robot never hits itself. Hits are world
positions; ``inf`` where a ray hits nothing within ``max_distance``.

Per-env state: the drifts (``drift_range``, ``ray_cast_drift_range``), drawn for every env and
kept where a reset's mask is set.
"""

from __future__ import annotations

import weakref
from typing import TYPE_CHECKING

import mujoco
import torch

from simlab.markers import VisualizationMarkers
from simlab.utils.env_mask import EnvIds, PerEnvState, env_mask
from simlab.utils.math import quat_apply, quat_apply_yaw, yaw_quat

from ..sensor_base import SensorBase, find_sensor_bodies
from .ray_caster_data import RayCasterData
from .ray_targets import RayTargets, find_target_geoms, target_model

if TYPE_CHECKING:
    from .ray_caster_cfg import RayCasterCfg

# Target models by simulation and geom ids: sensors casting at the same geometry share one.
_TARGET_MODELS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def ray_targets(sim, mesh_prim_paths: list[str], num_rays: int, owner: str) -> RayTargets:
    """A caster of ``num_rays`` rays against the geometry ``mesh_prim_paths`` names in ``sim``'s model
    (its target model shared by the sensors that cast at the same geoms)."""
    geoms = find_target_geoms(sim.model, list(mesh_prim_paths), owner)
    shared = _TARGET_MODELS.setdefault(sim, {})
    key = tuple(geoms)
    if key not in shared:
        shared[key] = target_model(sim.model, geoms)
    return RayTargets(shared[key], num_rays, sim.physics, sim.device)


class RayCaster(SensorBase):
    cfg: RayCasterCfg

    def __init__(self, cfg: RayCasterCfg, scene=None):
        from .ray_caster_cfg import RAY_ALIGNMENTS

        super().__init__(cfg, scene)
        owner = f"RayCasterCfg('{cfg.prim_path}')"
        if cfg.attach_yaw_only is not None:  # Isaac Lab's deprecated switch wins, as there
            self.cfg = cfg = cfg.replace(ray_alignment="yaw" if cfg.attach_yaw_only else "base")
        if cfg.ray_alignment not in RAY_ALIGNMENTS:
            raise ValueError(f"{owner}.ray_alignment='{cfg.ray_alignment}' is not one of {RAY_ALIGNMENTS}")
        if not cfg.max_distance > 0:
            raise ValueError(f"{owner}.max_distance must be > 0 [m], got {cfg.max_distance}")
        if not cfg.mesh_prim_paths:
            raise ValueError(
                f"{owner}.mesh_prim_paths is empty: name the geometry to cast against, e.g. ['/World/ground']"
            )
        unknown = set(cfg.ray_cast_drift_range) - {"x", "y", "z"}
        if unknown:
            raise ValueError(f"{owner}.ray_cast_drift_range takes keys 'x', 'y', 'z'; got {sorted(unknown)}")
        self._owner = owner
        self._data = RayCasterData()
        self._timestamp = 0.0
        self._outdated = True

    def __str__(self) -> str:
        return (
            f"RayCaster @ '{self.cfg.prim_path}': {self.num_rays} rays per env against {self.cfg.mesh_prim_paths},"
            f" alignment '{self.cfg.ray_alignment}'"
        )

    # -- Isaac Lab's API ------------------------------------------------------------------------

    @property
    def data(self) -> RayCasterData:
        """The hits, cast now if the body moved (an update was due) or envs were reset since the last cast."""
        if self._outdated and self._is_initialized:
            self._cast()
        return self._data

    def reset(self, env_ids: EnvIds = None) -> None:
        """Draw new drifts for the envs ``env_ids`` (ids or a bool mask); the next read casts again
        (the reset envs' bodies are placed after the sensors are reset, as in Isaac Lab)."""
        if self._is_initialized:
            self.state.reset(env_mask(env_ids, self.num_instances, self.device))
            self._outdated = True

    def update(self, dt: float, force_recompute: bool = False) -> None:
        """Called by the scene every physics step: marks the hits outdated every ``update_period``;
        they are cast when read (Isaac Lab's lazy update: a height scan read once per env step is
        cast once, not at every physics substep)."""
        if not self._is_initialized:
            return
        self._timestamp += dt
        if self.cfg.update_period > 0.0 and self._timestamp + 1e-9 < self.cfg.update_period and not force_recompute:
            return
        self._timestamp = 0.0
        self._outdated = True
        if force_recompute:
            self._cast()

    def _cast(self) -> None:
        self._outdated = False
        origins = self._sim.env_origins
        if self._free_pose is not None:  # a floating base's pose is its free joint's: no forward needed
            position, orientation = self._free_pose
            pos_w = self._qpos[:, position] + origins + self.drift
            quat_w = self._qpos[:, orientation]
        else:  # body poses only: the kinematics pass, not a forward's collision and constraint solve
            self._sim.physics.ensure_kinematics()
            pos_w = self._xpos[:, self._body_id] + origins + self.drift
            quat_w = self._xquat[:, self._body_id]
        self._data.pos_w.copy_(pos_w)
        self._data.quat_w.copy_(quat_w)
        starts, directions = self._rays_w(pos_w, quat_w)
        # the geometry sits at the same place in every world's own frame
        distance = self._targets.cast(starts - origins[:, None], directions).view(self.num_instances, self.num_rays)
        hit = (distance >= 0.0) & (distance <= self.cfg.max_distance)
        hits = torch.where(hit.unsqueeze(-1), starts + distance.unsqueeze(-1) * directions, torch.inf)
        hits[..., 2] += self.ray_cast_drift[:, 2:3]
        self._data.ray_hits_w.copy_(hits)

    # -- debug visualization: a marker at every hit --------------------------------------------

    def _set_debug_vis_impl(self, debug_vis: bool) -> None:
        if debug_vis and not hasattr(self, "ray_visualizer"):
            self.ray_visualizer = VisualizationMarkers(self.cfg.visualizer_cfg)
        if hasattr(self, "ray_visualizer"):
            self.ray_visualizer.set_visibility(debug_vis)

    def _debug_vis_callback(self, event) -> None:
        points = self.data.ray_hits_w.reshape(-1, 3)
        self.ray_visualizer.visualize(points[torch.isfinite(points).all(dim=1)])  # misses are inf: not drawn

    # -- building -------------------------------------------------------------------------------

    def _initialize(self, sim) -> None:
        model, device, n = sim.model, self.device, self.num_instances
        ids, names = find_sensor_bodies(model, self.cfg.prim_path, self._owner)
        if len(ids) != 1:
            raise ValueError(f"{self._owner} must select one body per env, it matches {names}")
        self._body_id = ids[0]
        starts, directions = self.cfg.pattern_cfg.func(self.cfg.pattern_cfg, device)
        offset_rot = torch.tensor(self.cfg.offset.rot, dtype=torch.float32, device=device)
        self.ray_starts = starts + torch.tensor(self.cfg.offset.pos, dtype=torch.float32, device=device)
        self.ray_directions = quat_apply(offset_rot.expand(len(directions), 4), directions)
        self.num_rays = len(self.ray_starts)
        self._xy = torch.tensor([1.0, 1.0, 0.0], device=device)  # drift in the plane only
        self._targets = ray_targets(sim, self.cfg.mesh_prim_paths, n * self.num_rays, self._owner)
        self._xpos, self._xquat = sim.physics.data("xpos"), sim.physics.data("xquat")
        # A body moved by a free joint has MuJoCo's world pose qpos[adr : adr + 7] (mj_kinematics
        # copies it): the sensor then reads it there, without the forward xpos would need.
        self._qpos, self._free_pose = sim.physics.data("qpos"), None
        joint = int(model.body_jntadr[self._body_id])
        if model.body_jntnum[self._body_id] == 1 and model.jnt_type[joint] == mujoco.mjtJoint.mjJNT_FREE:
            adr = int(model.jnt_qposadr[joint])
            self._free_pose = (slice(adr, adr + 3), slice(adr + 3, adr + 7))
        d = self._data
        d.pos_w = torch.zeros(n, 3, device=device)
        d.quat_w = torch.zeros(n, 4, device=device)
        d.ray_hits_w = torch.zeros(n, self.num_rays, 3, device=device)
        low, high = self.cfg.drift_range
        drift_range = torch.tensor(
            [self.cfg.ray_cast_drift_range.get(axis, (0.0, 0.0)) for axis in "xyz"], dtype=torch.float32, device=device
        )
        self.state = PerEnvState(n, device)
        self.drift = self.state.zeros("drift", (3,), reset=lambda: torch.empty(n, 3, device=device).uniform_(low, high))
        self.ray_cast_drift = self.state.zeros(
            "ray_cast_drift",
            (3,),
            reset=lambda: drift_range[:, 0] + torch.rand(n, 3, device=device) * (drift_range[:, 1] - drift_range[:, 0]),
        )
        self.state.reset(torch.ones(n, dtype=torch.bool, device=device))
        super()._initialize(sim)

    def _rays_w(self, pos_w: torch.Tensor, quat_w: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """(N, R, 3) ray starts and unit directions in the world frame (Isaac Lab's alignment rules)."""
        n, r = self.num_instances, self.num_rays
        drift_xy = torch.cat([self.ray_cast_drift[:, :2], torch.zeros_like(self.ray_cast_drift[:, 2:])], dim=-1)
        starts = self.ray_starts.expand(n, r, 3)
        directions = self.ray_directions.expand(n, r, 3)
        alignment = self.cfg.ray_alignment
        if alignment == "world":
            origin = pos_w + drift_xy
        elif alignment == "yaw":
            origin = pos_w + quat_apply_yaw(quat_w, drift_xy) * self._xy
            starts = quat_apply(yaw_quat(quat_w).unsqueeze(1), starts)
        else:  # "base"
            origin = pos_w + quat_apply(quat_w, drift_xy) * self._xy
            q = quat_w.unsqueeze(1)
            starts, directions = quat_apply(q, starts), quat_apply(q, directions)
        return starts + origin.unsqueeze(1), directions
