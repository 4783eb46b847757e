"""Rendering several envs side by side with MuJoCo Warp's ray tracer: video without OpenGL.

A GPU server often has no OpenGL library for offscreen rendering (no libEGL, no OSMesa). MuJoCo
Warp traces rays on the GPU itself, so simlab renders with it there. It draws what the OpenGL path
(:mod:`simlab.sim.renderer`) draws, by another route: each shown env is one world of a small
MuJoCo Warp batch, every world is rendered from the same camera moved by that env's offset, and the
images are merged pixel by pixel, the nearest surface winning (the depth test of one shared scene).

The render model is the scene's spec with one camera added; each call copies the shown envs' state
rows on the device, places the bodies (``kinematics``), points the camera, refits the ray tracer's
bounding volumes and renders. Debug-visualization markers are not drawn on this path.
"""

from __future__ import annotations

import contextlib
from collections.abc import Sequence

import mujoco
import numpy as np
import torch

__all__ = ["WarpRenderer", "camera_rotation"]

CAMERA_NAME = "simlab_video_camera"
FOVY_DEGREES = 45.0  # MuJoCo's free camera default, which the OpenGL path uses
MAX_DEPTH = 1.0e4  # metres; rays that hit nothing read as 0 and are treated as infinitely far


def camera_rotation(eye, lookat) -> np.ndarray:
    """The 3x3 world orientation of a MuJoCo camera at ``eye`` looking at ``lookat`` (columns: the
    camera's x right, y up, z backwards, as MuJoCo cameras look along their -z), z up."""
    forward = np.asarray(lookat, dtype=np.float64) - np.asarray(eye, dtype=np.float64)
    norm = np.linalg.norm(forward)
    if norm < 1e-9:
        raise ValueError(f"The camera eye {list(eye)} and look-at point {list(lookat)} coincide")
    forward /= norm
    right = np.cross(forward, [0.0, 0.0, 1.0])
    if np.linalg.norm(right) < 1e-6:  # looking straight down or up: any horizontal right will do
        right = np.array([0.0, -1.0, 0.0]) if forward[2] < 0 else np.array([0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    return np.stack([right, up, -forward], axis=1)


class WarpRenderer:
    """Renders RGB images of a few envs of a MuJoCo Warp simulation, side by side, on its device.

    Same interface as :class:`simlab.sim.renderer.OffscreenRenderer`.
    """

    def __init__(self, spec: mujoco.MjSpec, physics, width: int, height: int, max_envs: int = 16):
        if width < 1 or height < 1:
            raise ValueError(f"Render size must be positive, got {width}x{height}")
        import mujoco_warp as mjw
        import warp as wp

        self._wp, self._mjw = wp, mjw
        self.max_envs = max(1, min(max_envs, physics.num_envs))
        self.width, self.height = width, height
        self._device = str(physics.device)
        self._wp_device = wp.get_device(self._device if self._device.startswith("cuda") else "cpu")

        spec = spec.copy()
        spec.worldbody.add_camera(name=CAMERA_NAME, fovy=FOVY_DEGREES)
        self.model = spec.compile()
        if self.model.nq != physics.model.nq or self.model.nmocap != physics.model.nmocap:
            raise RuntimeError("The scene's spec no longer matches the simulated model; cannot render it")
        self._camera = self.model.camera(CAMERA_NAME).id
        n = self.max_envs
        with wp.ScopedDevice(self._wp_device):
            self._m = mjw.put_model(self.model)
            self._d = mjw.make_data(self.model, nworld=n)
            self._context = mjw.create_render_context(
                self.model,
                nworld=n,
                cam_res=(width, height),
                render_rgb=True,
                render_depth=True,
                cam_active=[CAMERA_NAME],
                render_skybox=True,  # a dome light's sky, as the OpenGL path draws it
            )
            self._rgb = wp.zeros((n, height, width), dtype=wp.vec3)
            self._depth = wp.zeros((n, height, width), dtype=float)
        self._state = {
            name: wp.to_torch(getattr(self._d, name))
            for name in ("qpos", "mocap_pos", "mocap_quat")
            if name == "qpos" or self.model.nmocap
        }
        self._cam_pos = wp.to_torch(self._d.cam_xpos)[:, self._camera]
        self._cam_rot = wp.to_torch(self._d.cam_xmat)[:, self._camera]

    def _scope(self):
        """Warp's device, and on the GPU torch's current stream: the copies and kernels stay ordered."""
        stack = contextlib.ExitStack()
        stack.enter_context(self._wp.ScopedDevice(self._wp_device))
        if self._wp_device.is_cuda:
            stream = self._wp.stream_from_torch(torch.cuda.current_stream(self._device))
            stack.enter_context(self._wp.ScopedStream(stream))
        return stack

    def render(self, physics, env_ids: Sequence[int], offsets: np.ndarray, eye, lookat) -> np.ndarray:
        """An (H, W, 3) uint8 image of the envs ``env_ids`` (``env_ids[0]`` the reference, ``offsets``
        their origins relative to it), seen from ``eye`` towards ``lookat`` in the reference's frame."""
        mjw = self._mjw
        count = min(len(env_ids), self.max_envs)
        ids = torch.as_tensor(list(env_ids)[:count], dtype=torch.long, device=self._device)
        shifts = torch.as_tensor(np.asarray(offsets, dtype=np.float32)[:count], device=self._device)
        with self._scope():
            for name, rows in self._state.items():
                rows[:count] = physics.data(name)[ids]
            mjw.kinematics(self._m, self._d)
            mjw.camlight(self._m, self._d)
            # env k's geoms sit at its own world's origin: moving the camera by -offset_k instead
            # draws them offset_k away from the reference's, as one shared scene would
            eye_t = torch.as_tensor(np.asarray(eye, dtype=np.float32), device=self._device)
            self._cam_pos[:count] = eye_t - shifts
            rotation = torch.as_tensor(camera_rotation(eye, lookat), dtype=torch.float32, device=self._device)
            self._cam_rot[:count] = rotation
            mjw.refit_bvh(self._m, self._d, self._context)
            mjw.render(self._m, self._d, self._context)
            mjw.get_rgb(self._context, 0, self._rgb)
            mjw.get_depth(self._context, 0, MAX_DEPTH, self._depth)
            rgb = self._wp.to_torch(self._rgb)[:count]
            depth = self._wp.to_torch(self._depth)[:count]
            depth = torch.where(depth > 0, depth, torch.inf)  # a ray that hit nothing
            nearest = depth.argmin(dim=0)  # (H, W): which env's surface each pixel sees
            image = torch.gather(rgb, 0, nearest[None, ..., None].expand(1, -1, -1, 3))[0]
            image = (image * 255.0).round_().clamp_(0, 255).to(torch.uint8)
        return image.cpu().numpy()

    def close(self) -> None:
        self._context = None
