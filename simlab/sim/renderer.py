"""Offscreen rendering of one world with MuJoCo's renderer and a free camera.

The backends keep the state on the device; to render world ``env_index`` its state (qpos, qvel,
mocap poses) is copied into a host ``MjData``, ``mj_forward`` places the bodies, and
``mujoco.Renderer`` draws the scene from a free camera set from an eye and a look-at point.

OpenGL: ``MUJOCO_GL`` picks the context. Unless already set, simlab uses ``egl`` when a CUDA device
is there and ``osmesa`` (software, Debian/Ubuntu package ``libosmesa6``) otherwise. MuJoCo reads
``MUJOCO_GL`` when it is first imported; if that happened before the variable was set here, the
chosen context class is installed into MuJoCo's renderer module before the first renderer is made.
"""

from __future__ import annotations

import math
import os

import mujoco
import numpy as np
import torch

_GL_PACKAGES = {"osmesa": "libosmesa6 (apt-get install libosmesa6)", "egl": "libegl1 and a GPU driver with EGL",
                "glfw": "a display and GLFW"}  # fmt: skip


def default_gl_backend() -> str:
    """``MUJOCO_GL`` if set, else ``egl`` with a CUDA device, else ``osmesa``."""
    return os.environ.setdefault("MUJOCO_GL", "egl" if torch.cuda.is_available() else "osmesa").lower()


def _install_gl_context(backend: str) -> None:
    """Make MuJoCo's renderer use ``backend``'s context even if mujoco was imported before the choice."""
    from mujoco.rendering.classic import gl_context

    if backend == "osmesa":
        from mujoco.osmesa import GLContext
    elif backend == "egl":
        from mujoco.egl import GLContext
    elif backend in ("glfw", "glx"):
        from mujoco.glfw import GLContext
    else:
        return
    gl_context.GLContext = GLContext


def look_at(eye, lookat) -> tuple[np.ndarray, float, float, float]:
    """MuJoCo free-camera parameters ``(lookat, distance, azimuth, elevation)`` (degrees) from an
    eye position and a point to look at."""
    eye, lookat = np.asarray(eye, dtype=np.float64), np.asarray(lookat, dtype=np.float64)
    forward = lookat - eye
    distance = float(np.linalg.norm(forward))
    if distance < 1e-9:
        raise ValueError(f"The camera eye {eye.tolist()} and look-at point {lookat.tolist()} coincide")
    forward /= distance
    azimuth = math.degrees(math.atan2(forward[1], forward[0]))
    elevation = math.degrees(math.asin(float(np.clip(forward[2], -1.0, 1.0))))
    return lookat, distance, azimuth, elevation


def fill_host_data(model: mujoco.MjModel, data: mujoco.MjData, physics, env_index: int) -> None:
    """Copy world ``env_index``'s state from the backend's tensors into a host ``MjData``."""
    data.qpos[:] = physics.data("qpos")[env_index].detach().cpu().numpy()
    data.qvel[:] = physics.data("qvel")[env_index].detach().cpu().numpy()
    if model.nmocap:
        data.mocap_pos[:] = physics.data("mocap_pos")[env_index].detach().cpu().numpy()
        data.mocap_quat[:] = physics.data("mocap_quat")[env_index].detach().cpu().numpy()


class OffscreenRenderer:
    """Renders RGB images of one world of a batched simulation."""

    def __init__(self, model: mujoco.MjModel, width: int, height: int):
        if width < 1 or height < 1:
            raise ValueError(f"Render size must be positive, got {width}x{height}")
        backend = default_gl_backend()
        _install_gl_context(backend)
        self.model = model
        # The offscreen buffer must hold the image; the model's default is 640x480.
        model.vis.global_.offwidth = max(model.vis.global_.offwidth, width)
        model.vis.global_.offheight = max(model.vis.global_.offheight, height)
        try:
            self._renderer = mujoco.Renderer(model, height=height, width=width)
        except Exception as err:  # noqa: BLE001 - GL errors come in many types
            need = _GL_PACKAGES.get(backend, "an OpenGL implementation")
            raise RuntimeError(
                f"Offscreen rendering with MUJOCO_GL={backend} failed: {err}. It needs {need}; or set MUJOCO_GL to"
                " another of egl, osmesa, glfw before starting python."
            ) from err
        self._data = mujoco.MjData(model)
        self._camera = mujoco.MjvCamera()
        self._camera.type = mujoco.mjtCamera.mjCAMERA_FREE

    def render(self, physics, env_index: int, eye, lookat) -> np.ndarray:
        """An (H, W, 3) uint8 image of world ``env_index`` seen from ``eye`` towards ``lookat``
        (both in that world's frame)."""
        fill_host_data(self.model, self._data, physics, env_index)
        mujoco.mj_forward(self.model, self._data)
        cam = self._camera
        cam.lookat[:], cam.distance, cam.azimuth, cam.elevation = look_at(eye, lookat)
        self._renderer.update_scene(self._data, camera=cam)
        # debug markers (simlab.markers) are decor geoms added on top of the model's own
        from simlab.markers.visualization_markers import add_markers_to_scene
        from simlab.sim.simulation_context import SimulationContext

        sim = SimulationContext.instance()
        add_markers_to_scene(self._renderer.scene, env_index, sim.env_origins if sim is not None else None)
        return self._renderer.render()

    def close(self) -> None:
        self._renderer.close()
