"""Camera images on the GPU: MuJoCo Warp's batched ray tracer renders every env in one call.

``mujoco_warp.create_render_context`` builds a bounding-volume hierarchy of the model's geoms in
every world; each render refits it to the current poses (``refit_bvh``) and traces one ray per pixel
(``render``). Both are recorded into the backend's CUDA graphs like the physics
(``CudaBackend.run_warp``), so a captured env step renders inside its graph. The packed results
are unpacked with torch ops on torch's stream: RGB from ``rgb_data`` (one uint32 per pixel, bytes
b, g, r, a), planar depth in metres from ``depth_data`` (0 where nothing is hit), and
``(object id, object type)`` pairs from ``seg_data``.
"""

from __future__ import annotations

import math

import mujoco
import torch

# Bytes per pixel and env of MuJoCo Warp's buffers: packed RGB (uint32), depth (float32), segmentation (2 x int32).
_CONTEXT_BYTES = {"rgb": 4, "depth": 4, "segmentation": 8}
_RENDERER_FUNCTIONS = ("create_render_context", "refit_bvh", "render")


def require_warp_renderer(mjw) -> None:
    """Raise if the installed ``mujoco_warp`` has no batched renderer."""
    missing = [name for name in _RENDERER_FUNCTIONS if not hasattr(mjw, name)]
    if missing:
        version = getattr(mjw, "__version__", "unknown")
        raise RuntimeError(
            f"GPU cameras need MuJoCo Warp's batched renderer, but the installed mujoco_warp ({version}) lacks"
            f" {', '.join(missing)}. Install the version simlab pins: pip install 'simlab[gpu]' (mujoco-warp==3.14.0)."
        )


def warp_context_bytes(num_envs: int, width: int, height: int, rgb: bool, depth: bool, segmentation: bool) -> int:
    """Device bytes of MuJoCo Warp's image buffers for one camera in ``num_envs`` worlds."""
    per_pixel = sum(
        size
        for name, size in _CONTEXT_BYTES.items()
        if {"rgb": rgb, "depth": depth, "segmentation": segmentation}[name]
    )
    return num_envs * width * height * per_pixel


class WarpCameraRenderer:
    """Renders model camera ``camera_id`` in every world of a ``CudaBackend`` (same outputs as
    :class:`~simlab.sensors.camera.mujoco_renderer.MujocoCameraRenderer`)."""

    def __init__(
        self,
        physics,
        model: mujoco.MjModel,
        camera_id: int,
        width: int,
        height: int,
        rgb: bool,
        depth: bool,
        segmentation: bool,
    ):
        from simlab.sim.backends.cuda import require_cuda_backend

        wp, mjw = require_cuda_backend(str(physics.device))
        require_warp_renderer(mjw)
        self._physics, self._mjw = physics, mjw
        self._width, self._height = width, height
        n = physics.num_envs
        with wp.ScopedDevice(physics.wp_device):
            self._context = mjw.create_render_context(
                model,
                nworld=n,
                cam_res=(width, height),
                render_rgb=[rgb],
                render_depth=[depth],
                render_seg=[segmentation],
                cam_active=[camera_id],
                enabled_geom_groups=[0, 1, 2],
                use_shadows=False,
                render_skybox=False,  # missed rays black, as the CPU camera draws them (no sky)
            )
            # One render outside any graph capture: it builds and loads the render kernel.
            self._refit_and_render()
        wp.synchronize_device(physics.wp_device)
        ctx = self._context
        self._packed_rgb = wp.to_torch(ctx.rgb_data) if rgb else None  # (N, H*W) uint32
        self._raw_depth = wp.to_torch(ctx.depth_data) if depth else None  # (N, H*W) float32
        self._raw_seg = wp.to_torch(ctx.seg_data) if segmentation else None  # (N, H*W, 2) int32
        device = physics.device
        self.rgb = torch.zeros(n, height, width, 3, dtype=torch.uint8, device=device) if rgb else None
        self.depth = torch.zeros(n, height, width, dtype=torch.float32, device=device) if depth else None
        self.geom_ids = torch.full((n, height, width), -1, dtype=torch.int32, device=device) if segmentation else None

    def _refit_and_render(self) -> None:
        m, d = self._physics.wp_model, self._physics.wp_data
        self._mjw.refit_bvh(m, d, self._context)
        self._mjw.render(m, d, self._context)

    def render(self) -> None:
        self._physics.run_warp(("camera", id(self)), self._refit_and_render)
        n, h, w = self._physics.num_envs, self._height, self._width
        if self.rgb is not None:
            bgra = self._packed_rgb.view(torch.uint8).view(n, h, w, 4)  # little-endian bytes of 0xAARRGGBB
            self.rgb.copy_(bgra[..., :3].flip(-1))  # b, g, r -> r, g, b (no index tensor: graph-capturable)
        if self.depth is not None:
            depth = self._raw_depth.view(n, h, w)
            self.depth.copy_(torch.where(depth > 0.0, depth, math.inf))
        if self.geom_ids is not None:
            seg = self._raw_seg.view(n, h, w, 2)
            is_geom = seg[..., 1] == int(mujoco.mjtObj.mjOBJ_GEOM)
            self.geom_ids.copy_(torch.where(is_geom, seg[..., 0], -1))

    def close(self) -> None:
        self._context = None
