"""The ray-cast camera: a pinhole depth camera made of one ray per pixel (Isaac Lab's ``RayCasterCamera``).

The rays go from the camera's origin through each pixel's centre (``PinholeCameraPatternCfg``), turn
with the camera's full pose, and are cast like the ray caster's, against a copy of the static target
geoms (``mesh_prim_paths``) with MuJoCo's ray functions: ``mj_ray`` on the CPU, ``mujoco_warp.rays``
on the GPU. Images are computed when read, after an update was due, as the ray caster's hits are.

The camera rides on a body, or on ``Xform`` groups made with ``create_prim`` (Isaac Lab's tutorial
puts one under ``/World/Origin_00`` and one under ``/World/Origin_01``): each group is one world,
as for assets under groups. ``set_world_poses`` / ``set_world_poses_from_view`` move the camera by
changing its offset in that frame, as in Isaac Lab.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, ClassVar

import torch

from simlab.utils.env_mask import env_ids_in_order, env_mask
from simlab.utils.math import (
    combine_frame_transforms,
    convert_camera_frame_orientation_convention,
    create_rotation_matrix_from_view,
    quat_apply,
    quat_from_matrix,
    quat_inv,
    quat_mul,
)

from ..camera.camera_data import CameraData
from ..sensor_base import SensorBase, find_sensor_bodies
from .ray_caster import RayCaster, ray_targets

if TYPE_CHECKING:
    from .ray_caster_camera_cfg import RayCasterCameraCfg

DATA_TYPES = ("distance_to_image_plane", "distance_to_camera", "normals")
"""What a ray-cast camera measures (``RayCasterCameraCfg.data_types``)."""

EnvIds = Sequence[int] | torch.Tensor | None
DEBUG_GRID = 32
"""``debug_vis`` draws the hits of every ``H / DEBUG_GRID``-th row and ``W / DEBUG_GRID``-th column."""


class RayCasterCamera(RayCaster):
    """Depth and surface-normal images of one camera per env; read them from ``data.output``."""

    cfg: RayCasterCameraCfg
    UNSUPPORTED_TYPES: ClassVar[set[str]] = {
        "rgb",
        "instance_id_segmentation",
        "instance_id_segmentation_fast",
        "instance_segmentation",
        "instance_segmentation_fast",
        "semantic_segmentation",
        "skeleton_data",
        "motion_vectors",
        "bounding_box_2d_tight",
        "bounding_box_2d_tight_fast",
        "bounding_box_2d_loose",
        "bounding_box_2d_loose_fast",
        "bounding_box_3d",
        "bounding_box_3d_fast",
    }
    """Isaac Lab's list of the types rays cannot give (they need a renderer: use ``Camera``)."""

    def __init__(self, cfg: RayCasterCameraCfg, scene=None):
        owner = f"RayCasterCameraCfg('{cfg.prim_path}')"
        _check_cfg(cfg, owner)
        super().__init__(cfg, scene)
        self._owner = owner
        self._data = CameraData()
        self._groups = _place_in_xform_groups(self._sim, cfg.prim_path)

    def __str__(self) -> str:
        n = self.num_instances
        return (
            f"Ray-Caster-Camera @ '{self.cfg.prim_path}':\n"
            f"\tframe                : {'Xform groups' if self._groups else 'body'}\n"
            f"\tupdate period (s)    : {self.cfg.update_period}\n"
            f"\tmeshes               : {list(self.cfg.mesh_prim_paths)}\n"
            f"\tnumber of sensors    : {n}\n"
            f"\tnumber of rays/sensor: {self.num_rays}\n"
            f"\ttotal number of rays : {self.num_rays * n}\n"
            f"\timage shape          : {self.image_shape}"
        )

    # -- Isaac Lab's API ------------------------------------------------------------------------

    @property
    def data(self) -> CameraData:
        """The images, cast now if an update was due since the last cast."""
        if self._outdated and self._is_initialized:
            self._cast()
        return self._data

    @property
    def image_shape(self) -> tuple[int, int]:
        """(height, width)."""
        return (self.cfg.pattern_cfg.height, self.cfg.pattern_cfg.width)

    @property
    def frame(self) -> torch.Tensor:
        """(N,) images cast since the last reset, per camera."""
        return self._frame

    def reset(self, env_ids: EnvIds = None) -> None:
        """Restart the frame count of the cameras ``env_ids``; the next read casts again."""
        if not self._is_initialized:
            return
        # a mask, not ids: the scene resets by mask inside the captured step (ids would read the device back)
        self._frame.masked_fill_(env_mask(env_ids, self.num_instances, self.device), 0)
        self._update_poses()
        self._outdated = True

    def set_world_poses(
        self,
        positions: torch.Tensor | None = None,
        orientations: torch.Tensor | None = None,
        env_ids: EnvIds = None,
        convention: str = "ros",
    ) -> None:
        """Place the cameras ``env_ids`` at world ``positions`` (M, 3) [m], turned to ``orientations``
        (M, 4) (w, x, y, z) in ``convention`` ("opengl", "ros" or "world"); None leaves that part.
        Stored as the offset from the frame the camera rides on, so it moves with that frame."""
        self._require_initialized("set_world_poses")
        ids = env_ids_in_order(env_ids, self.num_instances, self.device)
        view_pos, view_quat = self._view_pose()
        view_pos, view_quat = view_pos[ids], view_quat[ids]
        if positions is not None:
            positions = torch.as_tensor(positions, dtype=torch.float32, device=self.device).reshape(-1, 3)
            self._offset_pos[ids] = quat_apply(quat_inv(view_quat), positions - view_pos)
        if orientations is not None:
            orientations = torch.as_tensor(orientations, dtype=torch.float32, device=self.device).reshape(-1, 4)
            quat_w = convert_camera_frame_orientation_convention(orientations, origin=convention, target="world")
            self._offset_quat[ids] = quat_mul(quat_inv(view_quat), quat_w)
        self._update_poses()

    def set_world_poses_from_view(self, eyes: torch.Tensor, targets: torch.Tensor, env_ids: EnvIds = None) -> None:
        """Place the cameras ``env_ids`` at ``eyes`` (M, 3) looking at ``targets`` (M, 3), up along +z."""
        rotations = create_rotation_matrix_from_view(eyes, targets, up_axis="Z", device=self.device)
        self.set_world_poses(eyes, quat_from_matrix(rotations), env_ids, convention="opengl")

    def set_intrinsic_matrices(self, matrices: torch.Tensor, focal_length: float = 1.0, env_ids: EnvIds = None) -> None:
        """Give the cameras ``env_ids`` new (M, 3, 3) intrinsics; their rays follow."""
        self._require_initialized("set_intrinsic_matrices")
        ids = env_ids_in_order(env_ids, self.num_instances, self.device)
        self._data.intrinsic_matrices[ids] = torch.as_tensor(matrices, dtype=torch.float32, device=self.device)
        self._focal_length = focal_length
        starts, directions = self.cfg.pattern_cfg.func(
            self.cfg.pattern_cfg, self._data.intrinsic_matrices[ids], self.device
        )
        self.ray_starts[ids], self.ray_directions[ids] = starts, directions

    # -- casting --------------------------------------------------------------------------------

    def _cast(self) -> None:
        self._outdated = False
        n, r = self.num_instances, self.num_rays
        pos_w, quat_w = self._update_poses()
        q = quat_w.unsqueeze(1)
        starts = quat_apply(q, self.ray_starts) + pos_w.unsqueeze(1)
        directions = quat_apply(q, self.ray_directions)
        local = starts - self._sim.env_origins.unsqueeze(1)  # the geometry sits alike in every world's frame
        types = self.cfg.data_types
        if "normals" in types:
            distance, normal = self._targets.cast_with_normals(local, directions)
        else:
            distance, normal = self._targets.cast(local, directions), None
        hit = distance.view(n, r) >= 0.0
        depth = torch.where(hit, distance.view(n, r), math.inf)  # along the ray, from the camera's origin
        self.ray_hits_w = torch.where(hit.unsqueeze(-1), starts + depth.unsqueeze(-1) * directions, math.inf)
        out, shape, far = self._data.output, (n, *self.image_shape, 1), self.cfg.max_distance
        behaviour = self.cfg.depth_clipping_behavior
        if "distance_to_image_plane" in types:
            # along the camera's forward axis (x of its "world" convention frame); nan where nothing is hit
            plane = torch.where(hit, depth * self.ray_directions[..., 0], math.nan)
            if behaviour == "max":
                plane = torch.nan_to_num(plane.clamp(max=far), nan=far)
            elif behaviour == "zero":
                plane = torch.where(torch.isnan(plane) | (plane > far), 0.0, plane)
            out["distance_to_image_plane"].copy_(plane.view(shape))
        if "distance_to_camera" in types:
            if behaviour == "max":
                depth = depth.clamp(max=far)
            elif behaviour == "zero":
                depth = torch.where(depth > far, 0.0, depth)
            out["distance_to_camera"].copy_(depth.view(shape))
        if normal is not None:
            normal = torch.where(hit.unsqueeze(-1), normal.view(n, r, 3), math.inf)
            out["normals"].copy_(normal.view(n, *self.image_shape, 3))
        self._frame += 1

    def _view_pose(self) -> tuple[torch.Tensor, torch.Tensor]:
        """(N, 3) positions and (N, 4) orientations of the frames the cameras ride on, in the world."""
        origins = self._sim.env_origins
        if self._body_id is None:  # Xform groups: at their translations (the env origins), unturned
            return origins.clone(), self._identity.clone()
        self._sim.physics.ensure_kinematics()  # body poses only: no collision or constraint solve
        return self._xpos[:, self._body_id] + origins, self._xquat[:, self._body_id].clone()

    def _update_poses(self) -> tuple[torch.Tensor, torch.Tensor]:
        """The cameras' world poses ("world" convention) into ``data``; returned too."""
        pos_w, quat_w = combine_frame_transforms(*self._view_pose(), self._offset_pos, self._offset_quat)
        d = self._data
        d.pos_w.copy_(pos_w)
        d.quat_w_world.copy_(quat_w)
        d.quat_w_ros.copy_(convert_camera_frame_orientation_convention(quat_w, origin="world", target="ros"))
        d.quat_w_opengl.copy_(convert_camera_frame_orientation_convention(quat_w, origin="world", target="opengl"))
        return pos_w, quat_w

    # -- debug visualization: markers at a grid of hits ----------------------------------------

    def _debug_vis_callback(self, event) -> None:
        if self._outdated:
            self._cast()
        # a grid of at most DEBUG_GRID x DEBUG_GRID hits per camera: a render holds a few thousand markers,
        # and the first rows of a full image (its far edge) would take them all
        height, width = self.image_shape
        step_v, step_u = -(-height // DEBUG_GRID), -(-width // DEBUG_GRID)
        hits = self.ray_hits_w.view(self.num_instances, height, width, 3)[
            :, step_v // 2 :: step_v, step_u // 2 :: step_u
        ]
        points = hits.reshape(-1, 3)
        self.ray_visualizer.visualize(points[torch.isfinite(points).all(dim=1)])

    # -- building -------------------------------------------------------------------------------

    def _initialize(self, sim) -> None:
        n, device, cfg = self.num_instances, self.device, self.cfg
        self._body_id = None
        if not self._groups:
            ids, names = find_sensor_bodies(sim.model, cfg.prim_path, self._owner)
            if len(ids) != 1:
                raise ValueError(f"{self._owner} must select one body per env, it matches {names}")
            self._body_id = ids[0]
            self._xpos, self._xquat = sim.physics.data("xpos"), sim.physics.data("xquat")
        self._identity = torch.tensor([1.0, 0.0, 0.0, 0.0], device=device).repeat(n, 1)
        d = self._data
        d.image_shape = self.image_shape
        d.intrinsic_matrices = torch.tensor(cfg.pattern_cfg.intrinsic_matrix(), device=device).repeat(n, 1, 1)
        self._focal_length = cfg.pattern_cfg.focal_length
        self.ray_starts, self.ray_directions = cfg.pattern_cfg.func(cfg.pattern_cfg, d.intrinsic_matrices, device)
        self.num_rays = self.ray_directions.shape[1]
        self._targets = ray_targets(sim, cfg.mesh_prim_paths, n * self.num_rays, self._owner)
        self.ray_hits_w = torch.zeros(n, self.num_rays, 3, device=device)
        height, width = self.image_shape
        d.output = {
            name: torch.zeros(n, height, width, 3 if name == "normals" else 1, device=device) for name in cfg.data_types
        }
        d.info = [dict.fromkeys(cfg.data_types) for _ in range(n)]  # per camera, as Isaac Lab's
        d.pos_w = torch.zeros(n, 3, device=device)
        d.quat_w_world, d.quat_w_ros, d.quat_w_opengl = (torch.zeros(n, 4, device=device) for _ in range(3))
        offset_rot = torch.tensor([cfg.offset.rot], dtype=torch.float32, device=device)
        offset_rot = convert_camera_frame_orientation_convention(
            offset_rot, origin=cfg.offset.convention, target="world"
        )
        self._offset_quat = offset_rot.repeat(n, 1)
        self._offset_pos = torch.tensor([cfg.offset.pos], dtype=torch.float32, device=device).repeat(n, 1)
        self._frame = torch.zeros(n, dtype=torch.long, device=device)
        SensorBase._initialize(self, sim)  # not the ray caster's: no grid pattern, no drifts
        self._update_poses()
        self._outdated = True

    def _require_initialized(self, method: str) -> None:
        if not self._is_initialized:
            raise RuntimeError(f"{self._owner}.{method}: call sim.reset() first (the cameras exist from then on)")


def _check_cfg(cfg: RayCasterCameraCfg, owner: str) -> None:
    """One-line errors for what the ray-cast camera cannot do, saying what it can."""
    data_types = [cfg.data_types] if isinstance(cfg.data_types, str) else list(cfg.data_types)
    cfg.data_types = data_types
    rendered = sorted(set(data_types) & RayCasterCamera.UNSUPPORTED_TYPES)
    if rendered:
        raise ValueError(
            f"{owner}.data_types {rendered} need a renderer: rays give only {list(DATA_TYPES)};"
            " use simlab.sensors.CameraCfg for rendered images"
        )
    unknown = [name for name in data_types if name not in DATA_TYPES]
    if unknown or not data_types:
        raise ValueError(f"{owner}.data_types {data_types} has unknown types {unknown}; allowed: {list(DATA_TYPES)}")
    if not hasattr(cfg.pattern_cfg, "intrinsic_matrix"):
        raise ValueError(
            f"{owner}.pattern_cfg must be a patterns.PinholeCameraPatternCfg, got {type(cfg.pattern_cfg).__name__}"
        )
    cfg.pattern_cfg.intrinsic_matrix()  # checks the resolution and the lens
    if cfg.depth_clipping_behavior not in ("max", "zero", "none"):
        raise ValueError(
            f"{owner}.depth_clipping_behavior must be 'max', 'zero' or 'none', got {cfg.depth_clipping_behavior!r}"
        )
    if cfg.offset.convention not in ("opengl", "ros", "world"):
        raise ValueError(f"{owner}.offset.convention must be 'opengl', 'ros' or 'world', got {cfg.offset.convention!r}")
    drifts = {"drift_range": cfg.drift_range != (0.0, 0.0)}
    drifts["ray_cast_drift_range"] = any(tuple(v) != (0.0, 0.0) for v in cfg.ray_cast_drift_range.values())
    drifting = [name for name, set_ in drifts.items() if set_]
    if drifting:
        raise ValueError(f"{owner}.{drifting[0]}: Isaac Lab's ray-cast camera takes no drift; leave it at zero")


def _place_in_xform_groups(sim, prim_path: str) -> dict[str, tuple[float, float, float]]:
    """The ``create_prim`` groups ``prim_path`` names (one camera, and one world, per group, at its
    translation), set as the simulation's envs; empty when it names none (the camera rides on a body)."""
    from simlab.sim.utils import xform_groups

    groups = xform_groups(prim_path)
    if not groups:
        return groups
    origins = torch.tensor(list(groups.values()), dtype=torch.float32, device=sim.device)
    if sim.model is not None:
        raise RuntimeError(f"'{prim_path}': create the camera before sim.reset().")
    if sim.env_origins is not None and not torch.equal(sim.env_origins, origins):
        raise ValueError(
            f"'{prim_path}' matches {len(origins)} groups {origins.tolist()}, but the simulation already has env"
            f" origins {sim.env_origins.tolist()}: a camera on groups needs one group per world, at its origin."
        )
    sim.num_envs, sim.env_origins = len(origins), origins
    return groups
