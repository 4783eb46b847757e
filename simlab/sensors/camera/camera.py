"""Camera sensors: RGB, depth, normals and segmentation images of every env, as torch tensors.

The camera becomes an MJCF ``<camera>`` of the one model every env shares (on a body, or in the
env frame), added just before the model compiles. Under ``create_prim`` groups
(``/World/Origin_.*/CameraSensor``, Isaac Lab's camera tutorial) there is one camera per group: in
the one world a script without groups for its objects has, each its own MJCF camera (CPU), or one
per world when the worlds are those groups. Images are rendered when ``data`` is read and
the scene has moved since the last render (physics steps, resets): on the CPU by MuJoCo's OpenGL
renderer env by env, on the GPU by MuJoCo Warp's ray tracer for all envs at once, inside the
captured env step. Both renderers return the same images of the same state (up to shading).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import mujoco
import torch

from simlab.sim.spawners.sensors import check_pinhole_cfg, vertical_aperture
from simlab.sim.utils import xform_group_origins
from simlab.utils.env_mask import env_ids_in_order
from simlab.utils.math import (
    convert_camera_frame_orientation_convention,
    create_rotation_matrix_from_view,
    matrix_from_quat,
    quat_from_matrix,
)

from ..sensor_base import SensorBase
from .camera_data import CameraData
from .warp_renderer import warp_context_bytes

if TYPE_CHECKING:
    from .camera_cfg import CameraCfg, TiledCameraCfg

DATA_TYPES = (
    "rgb",
    "rgba",
    "depth",
    "distance_to_image_plane",
    "distance_to_camera",
    "normals",
    "semantic_segmentation",
    "instance_segmentation_fast",
    "instance_id_segmentation_fast",
)
"""The image types simlab's cameras render (``CameraCfg.data_types``)."""

_DEPTH_TYPES = ("depth", "distance_to_image_plane", "distance_to_camera")
_SEGMENTATION_TYPES = ("semantic_segmentation", "instance_segmentation_fast", "instance_id_segmentation_fast")
"""Bodies for the semantic and instance images (MuJoCo models have no semantic classes), geoms for instance ids."""
_ENV_PREFIXES = ("{ENV_REGEX_NS}/", "/World/envs/env_.*/", "/World/envs/env_0/")
# Bytes per pixel of each output image (seg: RGBA colours, or one int32 id: both 4 bytes).
_OUTPUT_BYTES = {
    "rgb": 3,
    "rgba": 4,
    "normals": 12,
    **dict.fromkeys(_SEGMENTATION_TYPES, 4),
    **dict.fromkeys(_DEPTH_TYPES, 4),
}
GPU_MEMORY_HEADROOM = 0.9
"""Share of the free GPU memory the camera's buffers may take."""


def check_camera_cfg(cfg: CameraCfg) -> None:
    """Errors for a camera config simlab cannot render, saying what is allowed."""
    data_types = [cfg.data_types] if isinstance(cfg.data_types, str) else list(cfg.data_types)
    unknown = [name for name in data_types if name not in DATA_TYPES]
    if unknown or not data_types:
        raise ValueError(
            f"{type(cfg).__name__}('{cfg.prim_path}').data_types {data_types} has unknown types {unknown};"
            f" allowed (a list of any of them): {list(DATA_TYPES)}"
        )
    for name in ("width", "height"):
        value = getattr(cfg, name)
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise ValueError(f"{type(cfg).__name__}.{name} must be a positive number of pixels, got {value!r}")
    if cfg.spawn is None:
        raise ValueError(
            f"{type(cfg).__name__}('{cfg.prim_path}').spawn is None: simlab has no existing camera to wrap;"
            " give a lens, e.g. spawn=sim_utils.PinholeCameraCfg()"
        )
    check_pinhole_cfg(cfg.spawn)
    if cfg.semantic_filter not in ("*:*", ["*:*"]):
        raise ValueError(
            f"{type(cfg).__name__}.semantic_filter={cfg.semantic_filter!r}: MuJoCo models have no semantic labels;"
            " simlab's semantic_segmentation labels every body (leave semantic_filter='*:*')"
        )
    if cfg.offset.convention not in ("opengl", "ros", "world"):
        raise ValueError(
            f"CameraCfg.OffsetCfg.convention must be 'opengl', 'ros' or 'world', got {cfg.offset.convention!r}"
        )


def camera_parent(prim_path: str) -> tuple[str | None, str]:
    """``(body, camera name)`` of a camera prim path: body None for a camera in the env frame
    (``{ENV_REGEX_NS}/Camera``), else the model body it rides on (``{ENV_REGEX_NS}/Robot/base/cam``
    -> ``Robot/base``)."""
    path = prim_path
    for prefix in _ENV_PREFIXES:
        if path.startswith(prefix):
            path = path[len(prefix) :]
            break
    else:
        raise ValueError(
            f"Camera prim_path '{prim_path}' must start with {{ENV_REGEX_NS}}/ (a camera in every env), e.g."
            " '{ENV_REGEX_NS}/Camera' or '{ENV_REGEX_NS}/Robot/base/front_cam'"
        )
    *parents, name = path.rstrip("/").split("/")
    if not name or any(c in name for c in "*.[]()"):
        raise ValueError(f"Camera prim_path '{prim_path}' must end in a plain name, e.g. '{{ENV_REGEX_NS}}/Camera'")
    return ("/".join(parents) or None), name


def camera_memory_bytes(num_envs: int, width: int, height: int, data_types: Sequence[str], gpu: bool) -> int:
    """Memory a camera's images take in ``num_envs`` envs: the outputs, the renderer's raw images and,
    on the GPU, MuJoCo Warp's buffers."""
    pixels = num_envs * width * height
    total = sum(_OUTPUT_BYTES[name] for name in data_types) * pixels
    rgb = any(name in ("rgb", "rgba") for name in data_types)
    depth = any(name in _DEPTH_TYPES for name in data_types)
    seg = any(name in _SEGMENTATION_TYPES for name in data_types)
    total += (3 * rgb + 4 * depth + 4 * seg) * pixels  # the renderer's unpacked images
    if gpu:
        total += warp_context_bytes(num_envs, width, height, rgb, depth, seg)
    return total


def check_gpu_memory(name: str, needed: int, free: int, num_envs: int, width: int, height: int) -> None:
    """Raise if ``needed`` bytes of camera images do not fit in ``free`` bytes of GPU memory."""
    if needed <= GPU_MEMORY_HEADROOM * free:
        return
    gib = 1024**3
    raise MemoryError(
        f"{name}: {num_envs} envs of {width}x{height} images need about {needed / gib:.2f} GiB of GPU memory,"
        f" but {free / gib:.2f} GiB are free. Lower the resolution (width, height), the number of envs"
        " (--num_envs) or the data_types."
    )


class Camera(SensorBase):
    """Images of one camera in every env (Isaac Lab's ``Camera``); read them from ``data.output``."""

    cfg: CameraCfg

    def __init__(self, cfg: CameraCfg, scene=None):
        check_camera_cfg(cfg)
        super().__init__(cfg, scene)
        self._data_types = [cfg.data_types] if isinstance(cfg.data_types, str) else list(cfg.data_types)
        self._groups = None if cfg.prim_path.startswith(_ENV_PREFIXES) else xform_group_origins(cfg.prim_path)
        if self._groups is None:
            self._body, self._name = camera_parent(cfg.prim_path)
        else:  # under create_prim groups: a camera at each group (see _add_to_spec)
            self._body, self._name = None, camera_parent("{ENV_REGEX_NS}/" + cfg.prim_path.rsplit("/", 1)[-1])[1]
        if "normals" in self._data_types and not str(self.device).startswith("cpu"):
            raise ValueError(
                f"CameraCfg('{cfg.prim_path}').data_types: 'normals' are cast as rays on the CPU backend only;"
                " on the GPU use a RayCasterCameraCfg (normals of static geometry) or drop 'normals'"
            )
        self._sim.add_build_callback(self._add_to_spec)
        # MuJoCo's GL renderer must be closed, not collected: freeing its GL objects when collected would
        # delete objects of whatever other context is current then (another camera's)
        self._sim.add_clear_callback(self.close)
        self._data = CameraData()
        self._renderer = None
        self._needs_render = True
        self._timestamp = 0.0

    def __str__(self) -> str:
        where = "on body " + self._body if self._body else "in the env frame"
        if self._groups is not None:
            where = f"at {len(self._groups)} create_prim groups"
        return f"Camera @ '{self.cfg.prim_path}': {self.cfg.width}x{self.cfg.height} {self._data_types}, {where}"

    # -- Isaac Lab's API ------------------------------------------------------------------------

    @property
    def data(self) -> CameraData:
        """The images of the current state (rendered now if the scene moved since the last read)."""
        if self._is_initialized and self._needs_render:
            self._render()
        return self._data

    @property
    def image_shape(self) -> tuple[int, int]:
        return (self.cfg.height, self.cfg.width)

    @property
    def num_instances(self) -> int:
        """Cameras: one per env, or one per ``create_prim`` group when the groups share one world."""
        views = getattr(self, "_views", None)
        return len(views) if views is not None else self._sim.num_envs

    @property
    def frame(self) -> torch.Tensor:
        return self._frame

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> None:
        # the reset envs get new states: render again when read (all envs render in one pass)
        self._needs_render = True

    def set_world_poses(
        self,
        positions: torch.Tensor | None = None,
        orientations: torch.Tensor | None = None,
        env_ids: Sequence[int] | torch.Tensor | None = None,
        convention: str = "ros",
    ) -> None:
        """Place the cameras ``env_ids`` at world ``positions`` (M, 3) [m], turned to ``orientations`` (M, 4)
        (w, x, y, z) in ``convention`` ("opengl", "ros" or "world"); None leaves that part. The next read
        renders from there. Cameras fixed in the world (in the env frame, or at groups) on the CPU backend;
        one camera in every env frame takes one pose relative to its env origin."""
        owner = f"Camera('{self.cfg.prim_path}').set_world_poses"
        if not self._is_initialized:
            raise RuntimeError(f"{owner}: call sim.reset() first (the cameras exist from then on)")
        if self._body is not None or self._sim.physics.name == "cuda":
            raise NotImplementedError(
                f"{owner}: simlab moves cameras fixed in the world on the CPU backend only; place a camera on a"
                " body with CameraCfg.offset"
            )
        ids = env_ids_in_order(env_ids, self.num_instances, "cpu")
        if not self._per_group and len(set(ids.tolist())) != self.num_instances:
            raise ValueError(
                f"{owner}: the envs share one camera in the env frame; give a pose for every env (env_ids=None)"
            )
        model, origins = self._sim.model, self._sim.env_origins.cpu()
        envs = torch.tensor([env for env, _ in self._views])[ids]
        cams = [self._views[i][1] for i in ids.tolist()]
        if positions is not None:
            local = torch.as_tensor(positions, dtype=torch.float64).reshape(-1, 3).cpu() - origins[envs].double()
            self._write_camera_field(owner, model.cam_pos, cams, local)
        if orientations is not None:
            quats = torch.as_tensor(orientations, dtype=torch.float64).reshape(-1, 4).cpu()
            opengl = convert_camera_frame_orientation_convention(quats, origin=convention, target="opengl")
            self._write_camera_field(owner, model.cam_quat, cams, opengl / opengl.norm(dim=-1, keepdim=True))
        self._needs_render = True
        self._update_poses()

    def set_world_poses_from_view(
        self, eyes: torch.Tensor, targets: torch.Tensor, env_ids: Sequence[int] | torch.Tensor | None = None
    ) -> None:
        """Place the cameras ``env_ids`` at ``eyes`` (M, 3) looking at ``targets`` (M, 3), up along +z."""
        rotations = create_rotation_matrix_from_view(eyes, targets, up_axis="Z", device="cpu")
        self.set_world_poses(eyes, quat_from_matrix(rotations), env_ids, convention="opengl")

    @staticmethod
    def _write_camera_field(owner: str, field, cams: list[int], values: torch.Tensor) -> None:
        """``field[cam] = value`` per camera; a camera shared by several envs must get one value."""
        for cam in set(cams):
            rows = values[[i for i, c in enumerate(cams) if c == cam]]
            if not torch.allclose(rows, rows[:1], atol=1e-6):
                raise ValueError(
                    f"{owner}: the envs share one camera in the env frame, so it takes one pose relative to the env"
                    f" origin; got {rows.tolist()}"
                )
            field[cam] = rows[0].numpy()

    def update(self, dt: float, force_recompute: bool = False) -> None:
        """Called by the scene every physics step: the next read renders the new state."""
        self._timestamp += dt
        if force_recompute or self.cfg.update_period <= 0.0 or self._timestamp + 1e-9 >= self.cfg.update_period:
            self._timestamp = 0.0
            self._needs_render = True

    def device_memory_bytes(self) -> int:
        """GPU bytes of the renderer's own buffers (MuJoCo Warp allocates them outside torch); 0 on the CPU."""
        renderer = self._renderer
        if renderer is None or self._sim.physics.name != "cuda":
            return 0
        n, w, h = self.num_instances, self.cfg.width, self.cfg.height
        return warp_context_bytes(
            n, w, h, renderer.rgb is not None, renderer.depth is not None, renderer.geom_ids is not None
        )

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    # -- building -------------------------------------------------------------------------------

    def _add_to_spec(self, spec: mujoco.MjSpec) -> None:
        if self._body is not None and spec.body(self._body) is None:
            bodies = [body.name for body in spec.bodies if body.name and body.name != "world"]
            raise ValueError(
                f"Camera '{self.cfg.prim_path}' is on the body '{self._body}', which the model does not have;"
                f" bodies in the model: {bodies}. Attach it to one of them ('{{ENV_REGEX_NS}}/<body>/{self._name}')"
                f" or to the env frame ('{{ENV_REGEX_NS}}/{self._name}')."
            )
        offset = self.cfg.offset
        rot = torch.tensor(offset.rot, dtype=torch.float64)
        rot = convert_camera_frame_orientation_convention(rot, origin=offset.convention, target="opengl")
        self._camera_names, self._per_group = [self._name], False
        places = [tuple(offset.pos)]
        groups, num_envs = self._groups, self._sim.num_envs
        if groups is not None and not (len(groups) == num_envs > 1):  # the groups are not the worlds
            if num_envs != 1:
                raise ValueError(
                    f"Camera '{self.cfg.prim_path}' matches {len(groups)} create_prim groups but the simulation has"
                    f" {num_envs} worlds: put the cameras under the groups the assets are under, or the assets in one"
                    " world"
                )
            if not str(self.device).startswith("cpu"):
                raise ValueError(
                    f"Camera '{self.cfg.prim_path}': several cameras in one world render on the CPU backend only;"
                    " run with --device cpu, or make one camera per env ('{ENV_REGEX_NS}/Camera')"
                )
            self._camera_names = [f"{self._name}_{k}" for k in range(len(groups))]
            places = [tuple(g + o for g, o in zip(group, offset.pos, strict=True)) for group in groups]
            self._per_group = True
        for name, place in zip(self._camera_names, places, strict=True):
            self.cfg.spawn.func(
                f"/{name}",
                self.cfg.spawn,
                translation=place,
                orientation=rot.tolist(),
                resolution=(self.cfg.width, self.cfg.height),
                body=self._body,
            )
        # MuJoCo's near clipping plane is the model's (znear * extent): pull it in for a closer camera
        near = self.cfg.spawn.clipping_range[0]
        extent = spec.stat.extent if spec.stat.extent > 0 else 1.0
        if near < spec.visual.map.znear * extent:
            spec.visual.map.znear = near / extent

    def _initialize(self, sim) -> None:
        model = sim.model
        ids = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_CAMERA, name) for name in self._camera_names]
        if min(ids) < 0:
            raise RuntimeError(
                f"Camera '{self.cfg.prim_path}': the compiled model lacks the cameras {self._camera_names}"
            )
        self._camera_id = ids[0]
        # (env, MJCF camera) of each camera this sensor holds
        self._views = [(0, cam) for cam in ids] if self._per_group else [(env, ids[0]) for env in range(sim.num_envs)]
        n, w, h, dev = self.num_instances, self.cfg.width, self.cfg.height, self.device
        physics = sim.physics
        gpu = physics.name == "cuda"
        if gpu and str(dev).startswith("cuda"):
            free, _ = torch.cuda.mem_get_info(torch.device(dev))
            needed = camera_memory_bytes(n, w, h, self._data_types, gpu=True)
            check_gpu_memory(f"Camera '{self.cfg.prim_path}'", needed, free, n, w, h)
        wants_rgb = any(t in ("rgb", "rgba") for t in self._data_types)
        wants_depth = any(t in _DEPTH_TYPES for t in self._data_types)
        wants_seg = any(t in _SEGMENTATION_TYPES for t in self._data_types)
        if gpu:
            from .warp_renderer import WarpCameraRenderer

            self._renderer = WarpCameraRenderer(
                physics, model, self._camera_id, w, h, wants_rgb, wants_depth, wants_seg
            )
        else:
            from .mujoco_renderer import MujocoCameraRenderer

            self._renderer = MujocoCameraRenderer(
                physics, model, self._camera_id, w, h, wants_rgb, wants_depth, wants_seg, views=self._views
            )

        d = self._data
        d.image_shape = (h, w)
        d.output = {name: self._new_output(name) for name in self._data_types}
        d.intrinsic_matrices = self._intrinsics().expand(n, 3, 3).clone()
        self._ray_lengths = self._ray_length_per_depth(d.intrinsic_matrices[0])
        info: dict = dict.fromkeys(self._data_types)
        if wants_seg:
            self._geom_body = torch.as_tensor(model.geom_bodyid, dtype=torch.int32, device=dev)
            self._palette = _palette(model.nbody, dev)
            self._geom_palette = _palette(model.ngeom, dev)
            bodies = {b: model.body(b).name for b in range(model.nbody)}
            geoms = {
                g: model.geom(g).name or f"{bodies[int(model.geom_bodyid[g])]}/geom{g}" for g in range(model.ngeom)
            }
            for name in set(_SEGMENTATION_TYPES) & set(info):
                per_geom = name == "instance_id_segmentation_fast"
                labels, palette = (geoms, self._geom_palette) if per_geom else (bodies, self._palette)
                if self._colorized(name):  # keyed by colour, as Isaac Lab's colourised images
                    labels = {"(0, 0, 0, 0)": "BACKGROUND"} | {
                        str(tuple(palette[i + 1].tolist())): label for i, label in labels.items()
                    }
                info[name] = {"idToLabels": labels}
        d.info = [dict(info) for _ in range(n)]  # per camera, as Isaac Lab's
        if "normals" in self._data_types:  # each pixel centre's ray in the camera's (OpenGL) frame
            x, y = self._pixel_tangents(d.intrinsic_matrices[0])
            rays = torch.stack([x, -y, -torch.ones_like(x)], dim=-1).reshape(-1, 3)
            self._pixel_rays = rays / rays.norm(dim=-1, keepdim=True)
        self._cam_xpos, self._cam_xmat = physics.data("cam_xpos"), physics.data("cam_xmat")
        # rotations from OpenGL camera axes to ROS / world ones (made here: no host copies while rendering)
        identity = torch.eye(3, device=dev)
        self._ros_from_opengl = _rotation(convert_camera_frame_orientation_convention, identity, "ros")
        self._world_from_opengl = _rotation(convert_camera_frame_orientation_convention, identity, "world")
        for name in ("pos_w", "quat_w_world", "quat_w_ros", "quat_w_opengl"):
            setattr(d, name, torch.zeros(n, 3 if name == "pos_w" else 4, device=dev))
        self._frame = torch.zeros(n, dtype=torch.long, device=dev)
        super()._initialize(sim)
        self._update_poses()

    def _new_output(self, name: str) -> torch.Tensor:
        n, w, h, dev = self.num_instances, self.cfg.width, self.cfg.height, self.device
        if name in ("rgb", "rgba"):
            return torch.zeros(n, h, w, len(name), dtype=torch.uint8, device=dev)
        if name == "normals":
            return torch.zeros(n, h, w, 3, dtype=torch.float32, device=dev)
        if name in _SEGMENTATION_TYPES and self._colorized(name):
            return torch.zeros(n, h, w, 4, dtype=torch.uint8, device=dev)
        if name in _SEGMENTATION_TYPES:
            return torch.full((n, h, w, 1), -1, dtype=torch.int32, device=dev)
        return torch.zeros(n, h, w, 1, dtype=torch.float32, device=dev)

    def _colorized(self, name: str) -> bool:
        return {
            "semantic_segmentation": self.cfg.colorize_semantic_segmentation,
            "instance_segmentation_fast": self.cfg.colorize_instance_segmentation,
            "instance_id_segmentation_fast": self.cfg.colorize_instance_id_segmentation,
        }[name]

    def _intrinsics(self) -> torch.Tensor:
        """(3, 3) intrinsics of the pinhole lens at this resolution (square pixels, centred)."""
        w, h, lens = self.cfg.width, self.cfg.height, self.cfg.spawn
        fx = w * lens.focal_length / lens.horizontal_aperture
        fy = h * lens.focal_length / vertical_aperture(lens, w, h)
        return torch.tensor([[fx, 0.0, w / 2], [0.0, fy, h / 2], [0.0, 0.0, 1.0]], device=self.device)

    def _pixel_tangents(self, intrinsics: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """(H, W) x (right) and y (down) of each pixel centre's ray per unit of depth."""
        h, w = self.cfg.height, self.cfg.width
        v, u = torch.meshgrid(
            torch.arange(h, device=self.device) + 0.5, torch.arange(w, device=self.device) + 0.5, indexing="ij"
        )
        return (u - intrinsics[0, 2]) / intrinsics[0, 0], (v - intrinsics[1, 2]) / intrinsics[1, 1]

    def _ray_length_per_depth(self, intrinsics: torch.Tensor) -> torch.Tensor:
        """(H, W, 1): distance to the camera over distance to the image plane, per pixel centre."""
        x, y = self._pixel_tangents(intrinsics)
        return torch.sqrt(1.0 + x * x + y * y).unsqueeze(-1)

    # -- rendering ------------------------------------------------------------------------------

    def _render(self) -> None:
        self._sim.physics.ensure_forward()  # cameras and geoms where the state puts them
        self._renderer.render()
        self._update_poses()
        renderer, output = self._renderer, self._data.output
        far = self.cfg.spawn.clipping_range[1]
        for name, image in output.items():
            if name == "rgb":
                image.copy_(renderer.rgb)
            elif name == "rgba":
                image[..., :3] = renderer.rgb
                image[..., 3] = 255
            elif name in _DEPTH_TYPES:
                depth = renderer.depth.unsqueeze(-1)
                if name == "distance_to_camera":
                    depth = depth * self._ray_lengths
                image.copy_(self._clip_depth(depth, far))
            elif name == "normals":
                image.copy_(self._cast_normals())
            else:
                hit = renderer.geom_ids >= 0
                geom = renderer.geom_ids.clamp(min=0).long()
                if name == "instance_id_segmentation_fast":  # one instance per geom
                    ids, palette = torch.where(hit, renderer.geom_ids, -1), self._geom_palette
                else:  # semantic and instance images: one per body
                    ids, palette = torch.where(hit, self._geom_body[geom], -1), self._palette
                image.copy_(palette[(ids + 1).long()] if self._colorized(name) else ids.unsqueeze(-1))
        self._frame += 1
        self._needs_render = False

    def _cast_normals(self) -> torch.Tensor:
        """(N, H, W, 3) unit normals of the surfaces each pixel's ray hits (zero where none): ``mj_ray`` from
        every camera, against its world's geoms of groups 0-2 (what the renderer draws), on the physics' threads."""
        import numpy as np

        physics, d = self._sim.physics, self._data
        envs = [env for env, _ in self._views]
        starts = d.pos_w - self._sim.env_origins[envs]  # in each world's own frame
        rotations = matrix_from_quat(d.quat_w_opengl)
        directions = torch.einsum("nij,pj->npi", rotations, self._pixel_rays)
        per_world = len(self._views) // physics.num_envs  # cameras are spread evenly: all in one, or one each
        pixels = directions.shape[1]
        pnt = starts.unsqueeze(1).expand(-1, pixels, 3).reshape(physics.num_envs, per_world * pixels, 3)
        vec = directions.reshape(physics.num_envs, per_world * pixels, 3)
        dist = np.zeros(vec.shape[:2], np.float32)
        normal = np.zeros(vec.shape, np.float32)
        groups = np.array([1, 1, 1, 0, 0, 0], np.uint8)
        physics.batch.rays(
            np.ascontiguousarray(pnt.numpy(), np.float32),
            np.ascontiguousarray(vec.numpy(), np.float32),
            dist,
            normal=normal,
            geomgroup=groups,
            flg_static=True,
        )
        return torch.from_numpy(normal).reshape(len(self._views), self.cfg.height, self.cfg.width, 3)

    def _clip_depth(self, depth: torch.Tensor, far: float) -> torch.Tensor:
        beyond = depth > far
        behaviour = self.cfg.depth_clipping_behavior
        if behaviour == "max":
            return torch.where(beyond, far, depth)
        if behaviour == "zero":
            return torch.where(beyond, 0.0, depth)
        return torch.where(beyond, math.inf, depth)

    def _update_poses(self) -> None:
        d = self._data
        if self._body is None and self._sim.physics.name != "cuda":
            # cameras fixed in the world: their poses are the model's, which set_world_poses moves (the CPU
            # physics holds a copy of the model; the renderer reads this one)
            envs, cams = zip(*self._views, strict=True)
            model = self._sim.model
            origins = self._sim.env_origins[list(envs)]
            d.pos_w.copy_(torch.as_tensor(model.cam_pos[list(cams)], dtype=torch.float32) + origins)
            opengl = matrix_from_quat(torch.as_tensor(model.cam_quat[list(cams)], dtype=torch.float32))
        else:
            d.pos_w.copy_(self._cam_xpos[:, self._camera_id] + self._sim.env_origins)
            opengl = self._cam_xmat[:, self._camera_id].reshape(-1, 3, 3)  # MuJoCo's camera frame is OpenGL's
        d.quat_w_opengl.copy_(quat_from_matrix(opengl))
        # R_convention = R_opengl @ (convention from OpenGL); the constant matrices live on the device
        d.quat_w_ros.copy_(quat_from_matrix(opengl @ self._ros_from_opengl))
        d.quat_w_world.copy_(quat_from_matrix(opengl @ self._world_from_opengl))


class TiledCamera(Camera):
    """Isaac Lab's ``TiledCamera``: simlab's cameras render every env in one batch already.

    Its ``data.info`` is one dict by data type for all cameras (Isaac Lab's tiled layout), where
    ``Camera``'s is a list of such dicts, one per camera."""

    cfg: TiledCameraCfg

    def _initialize(self, sim) -> None:
        super()._initialize(sim)
        self._data.info = dict(self._data.info[0]) if self._data.info else {}


def _rotation(convert, identity: torch.Tensor, target: str) -> torch.Tensor:
    """The constant (3, 3) that turns an OpenGL camera rotation into a ``target`` one (right-multiplied)."""
    from simlab.utils.math import matrix_from_quat

    return matrix_from_quat(convert(quat_from_matrix(identity), "opengl", target))


def _palette(num_bodies: int, device) -> torch.Tensor:
    """(num_bodies + 1, 4) uint8 RGBA colours: row 0 (nothing hit) transparent black, then one
    distinct opaque colour per body (golden-ratio hues)."""
    hues = (torch.arange(num_bodies, dtype=torch.float64) * 0.618033988749895) % 1.0
    channels = torch.stack([(hues + shift) % 1.0 for shift in (0.0, 1 / 3, 2 / 3)], dim=-1)
    rgb = (255 * (0.5 + 0.5 * torch.cos(2 * math.pi * channels))).round().to(torch.uint8)
    colours = torch.cat([rgb, torch.full((num_bodies, 1), 255, dtype=torch.uint8)], dim=-1)
    return torch.cat([torch.zeros(1, 4, dtype=torch.uint8), colours]).to(device)
