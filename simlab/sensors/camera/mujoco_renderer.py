"""Camera images on the CPU: MuJoCo's OpenGL renderer (EGL or OSMesa), one env after another.

Every env is its own MuJoCo world of one model, so one host ``MjData`` takes each env's state in
turn (qpos and mocap poses; kinematics place the bodies and cameras) and the model's camera is
rendered from it. Fit for small env counts; the GPU renders all envs in one call
(:mod:`.warp_renderer`).
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager

import mujoco
import numpy as np
import torch

from simlab.sim.renderer import gather_env_states, open_mujoco_renderer

# MuJoCo's renderer reads the far plane back as the depth of pixels that hit nothing.
_FAR_PLANE_FRACTION = 0.999


def geoms_only_option() -> mujoco.MjvOption:
    """Scene options that draw geoms of groups 0-2 and no sites, frames or decor (what MuJoCo Warp's
    ray tracer sees, so the two renderers show the same scene)."""
    option = mujoco.MjvOption()
    option.sitegroup[:] = 0
    option.geomgroup[:] = 0
    option.geomgroup[:3] = 1
    return option


@contextmanager
def _no_garbage_collection() -> Iterator[None]:
    """No cyclic garbage collection in the block: collecting an unclosed MuJoCo renderer (of an env nobody
    closed) frees its GL objects by id in whatever context is current, which mid-frame is this one's."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


class MujocoCameraRenderer:
    """Renders model camera ``camera_id`` in every env of a CPU backend, or the ``views`` given: (env,
    camera id) pairs, one image each (several cameras in one world).

    After :meth:`render`, ``rgb`` (N, H, W, 3) uint8, ``depth`` (N, H, W) float32 planar depth in
    metres (inf where nothing is hit) and ``geom_ids`` (N, H, W) int32 (-1 where nothing is hit) hold
    the images asked for (the others are None).
    """

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
        views: list[tuple[int, int]] | None = None,
    ):
        self._physics = physics
        self._model = model
        self._views = views if views is not None else [(env, camera_id) for env in range(physics.num_envs)]
        # No multisampling: each pixel shows what its centre sees, as in MuJoCo Warp's ray tracer, so a
        # policy trained on one device's images plays on the other's (antialiased, a rail thinner than a
        # pixel shows here as a line the GPU's images lack). The context reads it once, when it is made.
        samples, model.vis.quality.offsamples = model.vis.quality.offsamples, 0
        try:
            self._renderer = open_mujoco_renderer(model, width, height, max_geom=max(1000, 2 * model.ngeom))
        finally:
            model.vis.quality.offsamples = samples
        # No mirror pass for reflective floors and no shadows: MuJoCo Warp's ray tracer draws neither
        # (use_shadows=False), and the mirror pass alone was 40 % of a 100 x 100 image drawn on the CPU.
        self._renderer.scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = 0
        self._renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = 0
        # No sky (a dome light's skybox, drawn in videos): MuJoCo Warp's ray tracer leaves missed rays
        # black here too, and policies were trained on images with a black background.
        self._renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SKYBOX] = 0
        self._data = mujoco.MjData(model)
        self._option = geoms_only_option()
        self._far = float(model.vis.map.zfar * model.stat.extent)
        n = len(self._views)
        self.rgb = torch.zeros(n, height, width, 3, dtype=torch.uint8) if rgb else None
        self.depth = torch.zeros(n, height, width, dtype=torch.float32) if depth else None
        self.geom_ids = torch.full((n, height, width), -1, dtype=torch.int32) if segmentation else None

    def render(self) -> None:
        with _no_garbage_collection():
            self._render_all()

    def _render_all(self) -> None:
        model, data, renderer = self._model, self._data, self._renderer
        envs = sorted({env for env, _ in self._views})
        states = gather_env_states(self._physics, envs)
        row = {env: i for i, env in enumerate(envs)}  # an env's row of states (list.index: n^2 for n envs)
        placed = None
        for image, (env, camera) in enumerate(self._views):
            if env != placed:  # the env's state, once for all its cameras
                for name, values in states.items():
                    getattr(data, name)[:] = values[row[env]]
                mujoco.mj_kinematics(model, data)
                mujoco.mj_comPos(model, data)
                mujoco.mj_camlight(model, data)
                placed = env
            renderer.update_scene(data, camera=camera, scene_option=self._option)
            if self.rgb is not None:
                renderer.render(out=self.rgb[image].numpy())
            if self.depth is not None:
                renderer.enable_depth_rendering()
                depth = renderer.render()
                renderer.disable_depth_rendering()
                depth[depth >= _FAR_PLANE_FRACTION * self._far] = np.inf
                self.depth[image] = torch.from_numpy(depth)
            if self.geom_ids is not None:
                renderer.enable_segmentation_rendering()
                ids = renderer.render()
                renderer.disable_segmentation_rendering()
                is_geom = ids[..., 1] == mujoco.mjtObj.mjOBJ_GEOM
                self.geom_ids[image] = torch.from_numpy(np.where(is_geom, ids[..., 0], -1).astype(np.int32))

    def close(self) -> None:
        self._renderer.close()
