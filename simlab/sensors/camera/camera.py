"""Camera sensors: RGB, depth and segmentation images of every env, as torch tensors.

The camera becomes an MJCF ``<camera>`` of the one model every env shares (on a body, or in the
env frame), added just before the model compiles. Images are rendered when ``data`` is read and
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
from simlab.utils.math import convert_camera_frame_orientation_convention, quat_from_matrix

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
    "semantic_segmentation",
)
"""The image types simlab's cameras render (``CameraCfg.data_types``)."""

_DEPTH_TYPES = ("depth", "distance_to_image_plane", "distance_to_camera")
_ENV_PREFIXES = ("{ENV_REGEX_NS}/", "/World/envs/env_.*/", "/World/envs/env_0/")
# Bytes per pixel of each output image (seg: RGBA colours, or one int32 id: both 4 bytes).
_OUTPUT_BYTES = {"rgb": 3, "rgba": 4, "semantic_segmentation": 4, **dict.fromkeys(_DEPTH_TYPES, 4)}
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
    seg = "semantic_segmentation" in data_types
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
        self._body, self._name = camera_parent(cfg.prim_path)
        self._sim.add_build_callback(self._add_to_spec)
        # MuJoCo's GL renderer must be closed, not collected: freeing its GL objects when collected would
        # delete objects of whatever other context is current then (another camera's)
        self._sim.add_clear_callback(self.close)
        self._data = CameraData()
        self._renderer = None
        self._needs_render = True
        self._timestamp = 0.0

    def __str__(self) -> str:
        return (
            f"Camera @ '{self.cfg.prim_path}': {self.cfg.width}x{self.cfg.height} {self._data_types},"
            f" {'on body ' + self._body if self._body else 'in the env frame'}"
        )

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
    def frame(self) -> torch.Tensor:
        return self._frame

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> None:
        # the reset envs get new states: render again when read (all envs render in one pass)
        self._needs_render = True

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
        self.cfg.spawn.func(
            self.cfg.prim_path,
            self.cfg.spawn,
            translation=offset.pos,
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
        self._camera_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_CAMERA, self._name)
        if self._camera_id < 0:
            raise RuntimeError(f"Camera '{self.cfg.prim_path}': the compiled model has no camera '{self._name}'")
        n, w, h, dev = self.num_instances, self.cfg.width, self.cfg.height, self.device
        physics = sim.physics
        gpu = physics.name == "cuda"
        if gpu and str(dev).startswith("cuda"):
            free, _ = torch.cuda.mem_get_info(torch.device(dev))
            needed = camera_memory_bytes(n, w, h, self._data_types, gpu=True)
            check_gpu_memory(f"Camera '{self.cfg.prim_path}'", needed, free, n, w, h)
        wants_rgb = any(t in ("rgb", "rgba") for t in self._data_types)
        wants_depth = any(t in _DEPTH_TYPES for t in self._data_types)
        wants_seg = "semantic_segmentation" in self._data_types
        if gpu:
            from .warp_renderer import WarpCameraRenderer as Renderer
        else:
            from .mujoco_renderer import MujocoCameraRenderer as Renderer
        self._renderer = Renderer(physics, model, self._camera_id, w, h, wants_rgb, wants_depth, wants_seg)

        d = self._data
        d.image_shape = (h, w)
        d.output = {name: self._new_output(name) for name in self._data_types}
        d.intrinsic_matrices = self._intrinsics().expand(n, 3, 3).clone()
        self._ray_lengths = self._ray_length_per_depth(d.intrinsic_matrices[0])
        if wants_seg:
            self._geom_body = torch.as_tensor(model.geom_bodyid, dtype=torch.int32, device=dev)
            self._palette = _palette(model.nbody, dev)
            d.info["semantic_segmentation"] = {"idToLabels": {b: model.body(b).name for b in range(model.nbody)}}
        self._cam_xpos, self._cam_xmat = physics.data("cam_xpos"), physics.data("cam_xmat")
        # rotations from OpenGL camera axes to ROS / world ones (made here: no host copies while rendering)
        identity = torch.eye(3, device=dev)
        self._ros_from_opengl = _rotation(convert_camera_frame_orientation_convention, identity, "ros")
        self._world_from_opengl = _rotation(convert_camera_frame_orientation_convention, identity, "world")
        for name in ("pos_w", "quat_w_world", "quat_w_ros", "quat_w_opengl"):
            setattr(d, name, torch.zeros(n, 3 if name == "pos_w" else 4, device=dev))
        self._frame = torch.zeros(n, dtype=torch.long, device=dev)
        super()._initialize(sim)

    def _new_output(self, name: str) -> torch.Tensor:
        n, w, h, dev = self.num_instances, self.cfg.width, self.cfg.height, self.device
        if name in ("rgb", "rgba"):
            return torch.zeros(n, h, w, len(name), dtype=torch.uint8, device=dev)
        if name == "semantic_segmentation" and self.cfg.colorize_semantic_segmentation:
            return torch.zeros(n, h, w, 4, dtype=torch.uint8, device=dev)
        if name == "semantic_segmentation":
            return torch.full((n, h, w, 1), -1, dtype=torch.int32, device=dev)
        return torch.zeros(n, h, w, 1, dtype=torch.float32, device=dev)

    def _intrinsics(self) -> torch.Tensor:
        """(3, 3) intrinsics of the pinhole lens at this resolution (square pixels, centred)."""
        w, h, lens = self.cfg.width, self.cfg.height, self.cfg.spawn
        fx = w * lens.focal_length / lens.horizontal_aperture
        fy = h * lens.focal_length / vertical_aperture(lens, w, h)
        return torch.tensor([[fx, 0.0, w / 2], [0.0, fy, h / 2], [0.0, 0.0, 1.0]], device=self.device)

    def _ray_length_per_depth(self, intrinsics: torch.Tensor) -> torch.Tensor:
        """(H, W, 1): distance to the camera over distance to the image plane, per pixel centre."""
        h, w = self.cfg.height, self.cfg.width
        v, u = torch.meshgrid(
            torch.arange(h, device=self.device) + 0.5, torch.arange(w, device=self.device) + 0.5, indexing="ij"
        )
        x = (u - intrinsics[0, 2]) / intrinsics[0, 0]
        y = (v - intrinsics[1, 2]) / intrinsics[1, 1]
        return torch.sqrt(1.0 + x * x + y * y).unsqueeze(-1)

    # -- rendering ------------------------------------------------------------------------------

    def _render(self) -> None:
        self._sim.physics.ensure_forward()  # cameras and geoms where the state puts them
        self._renderer.render()
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
            else:
                body = torch.where(renderer.geom_ids >= 0, self._geom_body[renderer.geom_ids.clamp(min=0).long()], -1)
                if self.cfg.colorize_semantic_segmentation:
                    image.copy_(self._palette[(body + 1).long()])
                else:
                    image.copy_(body.unsqueeze(-1))
        self._update_poses()
        self._frame += 1
        self._needs_render = False

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
        d.pos_w.copy_(self._cam_xpos[:, self._camera_id] + self._sim.env_origins)
        opengl = self._cam_xmat[:, self._camera_id].reshape(-1, 3, 3)  # MuJoCo's camera frame is OpenGL's
        d.quat_w_opengl.copy_(quat_from_matrix(opengl))
        # R_convention = R_opengl @ (convention from OpenGL); the constant matrices live on the device
        d.quat_w_ros.copy_(quat_from_matrix(opengl @ self._ros_from_opengl))
        d.quat_w_world.copy_(quat_from_matrix(opengl @ self._world_from_opengl))


class TiledCamera(Camera):
    """Isaac Lab's ``TiledCamera``: simlab's cameras render every env in one batch already."""

    cfg: TiledCameraCfg


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
