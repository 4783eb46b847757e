"""Drawing several envs of a batched simulation into one MuJoCo scene, and rendering it offscreen.

Every env is its own MuJoCo world centred on zero; Isaac Lab's world places env ``i`` at
``scene.env_origins[i]``. To show neighbouring envs side by side as Isaac Lab does, the scene is
built in the frame of one *reference* env: its world is drawn as MuJoCo draws it
(``mjv_updateScene``), and each other shown env's geoms are appended (``mjv_addGeoms``) and moved
by that env's origin relative to the reference's. Ground planes (infinite, or on the world body) are drawn once.

The state of the shown envs only is copied from the backend's tensors (CPU or GPU) into one host
``MjData``, one env after another, and ``mj_forward`` places their bodies.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager

import mujoco
import numpy as np
import torch

from simlab.utils.gl_backend import GLBackendError, choose_gl_backend

__all__ = [
    "EnvSceneBuilder",
    "OffscreenRenderer",
    "SceneDecor",
    "add_scene_decor",
    "draw_decor",
    "gather_env_states",
    "look_at",
    "open_mujoco_renderer",
    "set_free_camera",
]

_STATE_FIELDS = ("qpos", "qvel", "mocap_pos", "mocap_quat")

# What layers above draw on top of the model's own geoms (simlab.markers registers its debug markers
# when it is imported): ``draw(scene, env_index, env_origins)`` after each render's geoms are built.
_SCENE_DECOR: list[Callable[[mujoco.MjvScene, int, torch.Tensor | None], None]] = []


def add_scene_decor(draw: Callable[[mujoco.MjvScene, int, torch.Tensor | None], None]) -> None:
    """Have every offscreen render call ``draw(scene, env_index, env_origins)`` (once per function)."""
    if draw not in _SCENE_DECOR:
        _SCENE_DECOR.append(draw)


DecorGeom = tuple[int, np.ndarray, np.ndarray, np.ndarray, np.ndarray]
"""One decor geom as plain arrays: (type, size, pos, mat, rgba)."""


class SceneDecor:
    """The decor (debug markers) of one env as plain arrays, for a live viewer that draws in its own
    thread: :meth:`capture` runs the render callbacks (debug visualization places its markers) and
    draws the registered decor into a scratch scene, here in the simulation's thread."""

    def __init__(self, model: mujoco.MjModel, max_geoms: int = 2000):
        self._scene = mujoco.MjvScene(model, maxgeom=max_geoms)

    def capture(self, env_index: int, env_origins: torch.Tensor | None) -> list[DecorGeom]:
        from simlab.sim.simulation_context import SimulationContext

        sim = SimulationContext.instance()
        if sim is not None:
            sim.run_render_callbacks()
        scene = self._scene
        scene.ngeom = 0
        for draw in _SCENE_DECOR:
            draw(scene, env_index, env_origins)
        return [
            (int(g.type), g.size.copy(), g.pos.copy(), g.mat.copy(), g.rgba.copy())
            for g in (scene.geoms[i] for i in range(scene.ngeom))
        ]


def draw_decor(scene: mujoco.MjvScene, decor: Sequence[DecorGeom]) -> None:
    """Append captured decor geoms to ``scene`` (as many as it has room for)."""
    for geom_type, size, pos, mat, rgba in decor:
        if scene.ngeom >= scene.maxgeom:
            return
        mujoco.mjv_initGeom(scene.geoms[scene.ngeom], geom_type, size, pos, mat.reshape(-1), rgba)
        scene.ngeom += 1


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


def set_free_camera(cam: mujoco.MjvCamera, eye, lookat) -> None:
    """Point MuJoCo free camera ``cam`` from ``eye`` at ``lookat``."""
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE
    cam.lookat[:], cam.distance, cam.azimuth, cam.elevation = look_at(eye, lookat)


def gather_env_states(physics, env_ids: Sequence[int]) -> dict[str, np.ndarray]:
    """The state rows (qpos, qvel, mocap poses) of the envs ``env_ids``: one small copy per field."""
    ids = torch.as_tensor(list(env_ids), dtype=torch.long)
    states = {}
    for name in _STATE_FIELDS:
        if name.startswith("mocap") and physics.model.nmocap == 0:
            continue
        field = physics.data(name)
        states[name] = field[ids.to(field.device)].detach().cpu().numpy()
    return states


# Geom fields an event may set per env (mdp.randomize_visual_color / randomize_rigid_body_scale)
_LOOK_FIELDS = ("geom_rgba", "geom_size", "geom_pos")
# the geom types whose drawn size (mjvGeom.size) is the model's geom_size
_SIZED_AS_MODEL = (int(mujoco.mjtGeom.mjGEOM_BOX), int(mujoco.mjtGeom.mjGEOM_ELLIPSOID))


def gather_env_looks(physics, env_ids: Sequence[int]) -> dict[str, np.ndarray]:
    """The per-world geom colors, sizes and positions of the envs ``env_ids``; a field no env has
    its own of is left out (the model's is drawn)."""
    looks = {}
    for name in _LOOK_FIELDS:
        field = physics.per_world_model_field(name)
        if field is not None:
            looks[name] = field[torch.as_tensor(list(env_ids), dtype=torch.long, device=field.device)].cpu().numpy()
    return looks


def _restyle(model: mujoco.MjModel, data: mujoco.MjData, geoms, looks: dict[str, np.ndarray], row: int) -> None:
    """Draw the model geoms among ``geoms`` (mjvGeoms of one env) with that env's own colors and sizes."""
    for geom in geoms:
        if geom.objtype != mujoco.mjtObj.mjOBJ_GEOM:
            continue
        gid = geom.objid
        if "geom_rgba" in looks:
            geom.rgba[:] = looks["geom_rgba"][row, gid]
        if "geom_size" in looks and int(model.geom_type[gid]) in _SIZED_AS_MODEL:
            geom.size[:] = looks["geom_size"][row, gid]
        if "geom_pos" in looks:  # moved within its body: turn the change into the world frame
            shift = looks["geom_pos"][row, gid] - model.geom_pos[gid]
            geom.pos += data.xmat[model.geom_bodyid[gid]].reshape(3, 3) @ shift


def _ground(model: mujoco.MjModel) -> np.ndarray:
    """Which geoms are the ground every env's world holds: infinite planes, and the planes
    ``spawn_ground_plane`` made (a terrain's, a scene's ``GroundPlaneCfg``), known by their material.
    Other planes (a finite wall or table top on the world body) are the envs' own."""
    from simlab.sim.spawners.from_files.from_files import GROUND_PLANE_MATERIAL

    plane = model.geom_type == mujoco.mjtGeom.mjGEOM_PLANE
    infinite = model.geom_size[:, :2].min(axis=1) <= 0
    spawned = [
        mat >= 0
        and (mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_MATERIAL, mat) or "").endswith(f"/{GROUND_PLANE_MATERIAL}")
        for mat in model.geom_matid
    ]
    return plane & (infinite | np.array(spawned, dtype=bool))


def _without_ground(model: mujoco.MjModel, world_geoms: bool = False) -> mujoco.MjModel:
    """A copy of ``model`` whose ground (a neighbour's copy, moved by its env offset, z-fights with the
    reference's) and, with ``world_geoms``, all static geoms of the world body are invisible (MuJoCo
    skips geoms with alpha 0)."""
    hidden = copy.deepcopy(model)
    ground = _ground(hidden)
    if world_geoms:
        ground |= hidden.geom_bodyid == 0
    hidden.geom_rgba[ground, 3] = 0.0
    hidden.geom_matid[ground] = -1  # a material's alpha would override the geom's
    return hidden


class EnvSceneBuilder:
    """Fills an ``MjvScene`` with a reference env and its neighbours, offset by their origins."""

    def __init__(self, model: mujoco.MjModel):
        self.model = model
        self.neighbour_model = _without_ground(model)
        # a neighbour drawn where it is (a shared terrain) would draw the terrain again on the reference's
        self.same_frame_neighbour_model = _without_ground(model, world_geoms=True)
        self.data = mujoco.MjData(model)
        self.option = mujoco.MjvOption()
        self._perturb = mujoco.MjvPerturb()

    def load(self, states: dict[str, np.ndarray], row: int) -> mujoco.MjData:
        """Row ``row`` of ``states`` in the host ``MjData``, its bodies placed."""
        for name, values in states.items():
            getattr(self.data, name)[:] = values[row]
        mujoco.mj_forward(self.model, self.data)
        return self.data

    def add_neighbours(
        self, scene: mujoco.MjvScene, states: dict[str, np.ndarray], offsets: np.ndarray, looks=None
    ) -> None:
        """Append the geoms of rows 1.. of ``states``, each moved by its row of ``offsets`` (metres)
        and drawn with its row of ``looks`` (``gather_env_looks``)."""
        catmask = int(mujoco.mjtCatBit.mjCAT_ALL)
        for row in range(1, len(offsets)):
            data = self.load(states, row)
            first = scene.ngeom
            model = self.same_frame_neighbour_model if not offsets[row].any() else self.neighbour_model
            mujoco.mjv_addGeoms(model, data, self.option, self._perturb, catmask, scene)
            if scene.ngeom == scene.maxgeom:
                break  # MuJoCo warns once; the scene shows the envs that fit
            for geom in scene.geoms[first : scene.ngeom]:
                geom.pos += offsets[row]
            if looks:
                _restyle(self.model, data, scene.geoms[first : scene.ngeom], looks, row)

    def build(
        self, scene: mujoco.MjvScene, states: dict[str, np.ndarray], offsets: np.ndarray, camera, looks=None
    ) -> None:
        """The whole scene: row 0 is the reference env (offset 0), the others its neighbours."""
        data = self.load(states, 0)
        mujoco.mjv_updateScene(
            self.model, data, self.option, self._perturb, camera, int(mujoco.mjtCatBit.mjCAT_ALL), scene
        )
        if looks:
            _restyle(self.model, data, scene.geoms[: scene.ngeom], looks, 0)
        self.add_neighbours(scene, states, offsets, looks)


def _install_gl_context(backend: str) -> None:
    """Make MuJoCo's renderer use ``backend``'s context even if mujoco was imported before the choice.

    This sets a module attribute of MuJoCo's (process-wide), so only with the release it was checked with."""
    from simlab.utils.versions import release_mismatch, warn_once

    if (mismatch := release_mismatch("mujoco")) is not None:
        warn_once(f"{mismatch}: MuJoCo's renderer picks its GL context from MUJOCO_GL itself")
        return
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


NEAR_CLIP_M = 0.05
"""Farthest distance [m] of the renderer's near clipping plane from the camera."""

HEADLIGHT_AMBIENT, HEADLIGHT_DIFFUSE = 0.3, 0.6
"""The least light of the camera's own lamp in the viewer's frames: the lights of a task's scene are
set for its camera sensors and, taken from Isaac Lab's intensities, often leave a frame dark."""


def view_znear(model: mujoco.MjModel) -> float:
    """``vis.map.znear`` that puts the near clipping plane at most ``NEAR_CLIP_M`` from the camera."""
    return min(model.vis.map.znear, NEAR_CLIP_M / max(model.stat.extent, 1e-6))


@contextmanager
def near_clip_limited(model: mujoco.MjModel) -> Iterator[None]:
    """Within the block, views of ``model`` clip at most ``NEAR_CLIP_M`` in front of the camera.

    MuJoCo's near clipping plane is a share of the model's extent (``vis.map.znear`` 0.01): on a
    generated terrain of 100+ m it cuts away everything within a metre of the camera, the ground in
    front of a camera that follows a robot included. Only the viewer's frames take the closer plane
    (camera sensors keep the model's, set from their ``clipping_range``), so it is restored after.
    """
    znear = model.vis.map.znear
    model.vis.map.znear = view_znear(model)
    try:
        yield
    finally:
        model.vis.map.znear = znear


def open_mujoco_renderer(model: mujoco.MjModel, width: int, height: int, max_geom: int = 1000) -> mujoco.Renderer:
    """MuJoCo's offscreen ``Renderer`` on the GL backend simlab chooses (EGL, else OSMesa).

    Raises:
        GLBackendError: no backend renders here, or the chosen one fails; the message says what to install.
    """
    backend = choose_gl_backend()
    # The offscreen buffer must hold the image; the model's default is 640x480.
    model.vis.global_.offwidth = max(model.vis.global_.offwidth, width)
    model.vis.global_.offheight = max(model.vis.global_.offheight, height)
    try:
        _install_gl_context(backend)
        return mujoco.Renderer(model, height=height, width=width, max_geom=max_geom)
    except Exception as err:  # noqa: BLE001 - GL errors come in many types
        raise GLBackendError(
            f"Offscreen rendering with MUJOCO_GL={backend} failed: {err}. Unset MUJOCO_GL to let simlab"
            " pick a working backend, or install one (Debian/Ubuntu: libosmesa6 for OSMesa, libegl1 for EGL)."
        ) from err


def light_up(scene: mujoco.MjvScene) -> None:
    """Raise the headlight (the lamp at the camera) of a built ``scene`` to at least the viewer's."""
    for light in scene.lights[: scene.nlight]:
        if light.headlight:
            np.maximum(light.ambient, HEADLIGHT_AMBIENT, out=light.ambient)
            np.maximum(light.diffuse, HEADLIGHT_DIFFUSE, out=light.diffuse)


class OffscreenRenderer:
    """Renders RGB images of a few envs of a batched simulation, side by side."""

    def __init__(self, model: mujoco.MjModel, width: int, height: int, max_envs: int = 16):
        if width < 1 or height < 1:
            raise ValueError(f"Render size must be positive, got {width}x{height}")
        self.model = model
        self.max_envs = max_envs
        samples = model.vis.quality.offsamples
        model.vis.quality.offsamples = 0  # no multisampling: it doubles the cost of a frame drawn on the CPU
        try:
            max_geom = max(1000, 2 * model.ngeom * max_envs)
            self._renderer = open_mujoco_renderer(model, width, height, max_geom=max_geom)
        finally:
            model.vis.quality.offsamples = samples  # camera sensors keep the model's
        # no mirror pass for reflective floors: a fifth of a frame drawn on the CPU, for a faint reflection
        self._renderer.scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = 0
        self._builder = EnvSceneBuilder(model)
        self._camera = mujoco.MjvCamera()

    def render(self, physics, env_ids: Sequence[int], offsets: np.ndarray, eye, lookat) -> np.ndarray:
        """An (H, W, 3) uint8 image of the envs ``env_ids`` seen from ``eye`` towards ``lookat``.

        ``env_ids[0]`` is the reference env: ``eye``, ``lookat`` and ``offsets`` (the env origins
        minus the reference's, one row per env) are in its frame.
        """
        states = gather_env_states(physics, env_ids)
        set_free_camera(self._camera, eye, lookat)
        looks = gather_env_looks(physics, env_ids)
        offsets = np.asarray(offsets, dtype=np.float32)
        with near_clip_limited(self.model):  # the camera's frustum is set when the scene is built
            self._builder.build(self._renderer.scene, states, offsets, self._camera, looks)
        light_up(self._renderer.scene)
        from simlab.sim.simulation_context import SimulationContext

        sim = SimulationContext.instance()
        if sim is not None:
            sim.run_render_callbacks()  # debug visualization (e.g. command arrows) places its markers
        for draw in _SCENE_DECOR:  # debug markers: decor geoms on top of the model's own
            draw(self._renderer.scene, int(env_ids[0]), sim.env_origins if sim is not None else None)
        return self._renderer.render()

    def close(self) -> None:
        self._renderer.close()
