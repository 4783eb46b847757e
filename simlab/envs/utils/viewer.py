"""The viewer camera of an env (``cfg.viewer``): where ``env.render()`` and the viewers look from,
which envs they show, and the offscreen renderer ``env.render()`` uses.

As in Isaac Lab, ``ViewerCfg.eye`` / ``lookat`` are given in the frame named by ``origin_type``:
the world (``"world"``), env ``env_index``'s origin (``"env"``), or the root / a body of asset
``asset_name`` in env ``env_index`` (``"asset_root"`` / ``"asset_body"``, following it as it moves).
Each env is its own MuJoCo world, so a frame is drawn in env ``env_index``'s world, with the
neighbouring envs nearest the look-at point drawn beside it at their origins.

A world-frame camera names a fixed point of the world, often its origin on the ground, wherever the
robots stand; the frames of ``env.render()`` keep its direction but look at the middle of what the
envs within the camera's reach of that point are about (where no env is, as between envs standing far
apart: env ``env_index`` and the envs within reach of it): their articulations (the robots) and the
objects lying near them, not the props they stand on nor objects kept far off (the parked instances
of a rigid object collection); no farther away than configured and closer where that would fill less
of the picture. The camera is aimed at the first frame and then moves only with the robots' roots,
once they have left a dead zone around the point it follows: a fixed-base arm never moves it (nor do
the objects it handles), a walking or running robot is followed smoothly, its gait's sway barely. The
other origin types name a point on an env or a robot and are kept as given.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

__all__ = [
    "MAX_SHOWN_ENVS",
    "ViewFrame",
    "camera_pose",
    "close_renderer",
    "render_frame",
    "renderer_kind",
    "show_in_viewer",
    "view_frame",
]

MAX_SHOWN_ENVS = 16
"""How many envs a frame shows at most (the reference env and its nearest neighbours)."""

ORIGIN_TYPES = ("world", "env", "asset_root", "asset_body")
RENDERERS = ("auto", "opengl", "warp")
NEAR = 0.5
"""An object is framed with the robots when it lies wholly in their box grown on every side by this
share of its largest side."""
FOLLOW = 0.1
"""The dead zone of a world-frame camera: it moves with the shown robots once the mean of their roots
lies farther than this share of its distance from the point it follows, and then just enough to
bring it back to the zone's edge (no jumps; a sway inside the zone does not move it)."""


@dataclass
class ViewFrame:
    """What to draw: envs (``env_ids[0]`` the reference), their origins relative to the reference's,
    and the camera, all in the reference env's MuJoCo frame."""

    env_ids: list[int]
    offsets: np.ndarray  # (len(env_ids), 3)
    eye: np.ndarray
    lookat: np.ndarray


def _frame_origin_w(env, viewer) -> np.ndarray:
    """The world-frame origin of the frame ``viewer.origin_type`` names."""
    index = viewer.env_index
    if viewer.origin_type == "world":
        return np.zeros(3)
    if viewer.origin_type == "env":
        return env.scene.env_origins[index].cpu().numpy().astype(np.float64)
    if viewer.origin_type in ("asset_root", "asset_body"):
        if viewer.asset_name is None:
            raise ValueError(f"cfg.viewer.origin_type='{viewer.origin_type}' needs cfg.viewer.asset_name")
        asset = env.scene[viewer.asset_name]
        if viewer.origin_type == "asset_root":
            pos = asset.data.root_pos_w[index]
        else:
            if viewer.body_name is None:
                raise ValueError("cfg.viewer.origin_type='asset_body' needs cfg.viewer.body_name")
            body_ids, _ = asset.find_bodies(viewer.body_name)
            pos = asset.data.body_pos_w[index, body_ids[0]]
        return pos.detach().cpu().numpy().astype(np.float64)
    raise ValueError(f"Unknown cfg.viewer.origin_type '{viewer.origin_type}'; allowed: {', '.join(ORIGIN_TYPES)}")


def camera_pose(env, viewer) -> tuple[np.ndarray, np.ndarray]:
    """The viewer's eye and look-at point in the MuJoCo frame of env ``viewer.env_index``."""
    index = viewer.env_index
    if not 0 <= index < env.num_envs:
        raise ValueError(f"cfg.viewer.env_index is {index}, but there are {env.num_envs} envs")
    origin_w = _frame_origin_w(env, viewer)
    # MuJoCo frame of env ``index``: the world shifted by its world's offset (zero on a shared terrain)
    ref_origin = env.sim.env_origins[index].cpu().numpy().astype(np.float64)
    eye = np.asarray(viewer.eye, dtype=np.float64) + origin_w - ref_origin
    lookat = np.asarray(viewer.lookat, dtype=np.float64) + origin_w - ref_origin
    return eye, lookat


def view_frame(env, viewer, max_envs: int = MAX_SHOWN_ENVS) -> ViewFrame:
    """The envs to draw and the camera: env ``viewer.env_index`` and the ``max_envs - 1`` envs
    whose origins are nearest the look-at point."""
    eye, lookat = camera_pose(env, viewer)
    frame_offsets = env.sim.env_origins.detach().cpu().numpy().astype(np.float64)
    origins = env.scene.env_origins.detach().cpu().numpy().astype(np.float64)
    ref = viewer.env_index
    offsets = frame_offsets - frame_offsets[ref]  # how far each world's geoms are moved when drawn
    local = origins[:, :2] - frame_offsets[ref, :2]  # the env origins in the reference's frame
    reach = float(np.linalg.norm(eye - lookat))
    distance = np.linalg.norm(local - lookat[:2], axis=1)
    if viewer.origin_type == "world" and not (distance <= reach).any():
        # no env within the camera's reach of the world point it names (envs far apart, that point
        # between them): the camera is about the reference env and the envs within reach of it
        distance = np.linalg.norm(local - local[ref], axis=1)
    order = distance.copy()
    order[ref] = -1.0  # the reference env comes first
    env_ids = np.argsort(order, kind="stable")[: max(1, max_envs)].tolist()
    frame = ViewFrame(env_ids, offsets[env_ids], eye, lookat)
    if viewer.origin_type != "world":
        return frame
    # the envs in the camera's reach of the look-at point (the reference env may stand far off)
    near = distance[env_ids] <= reach
    rows = near if near.any() else np.ones(len(env_ids), bool)
    # aimed at the first frame (and again when the shown envs or the configured camera change), then
    # moved only with the robots' roots: not chasing a falling object or a swinging arm
    key = (tuple(env_ids), tuple(eye), tuple(lookat), tuple(rows), tuple(viewer.resolution))
    aim = getattr(env, "_view_aim", None)
    roots = _roots(env, frame, rows)
    if aim is None or aim[0] != key:
        aim = (key, *_aim(env, frame, rows, viewer.resolution), roots)
    else:
        aim = (key, *_follow(*aim[1:], roots))
    env._view_aim = aim
    return ViewFrame(frame.env_ids, frame.offsets, aim[1].copy(), aim[2].copy())


def _roots(env, frame: ViewFrame, rows: np.ndarray) -> np.ndarray | None:
    """The mean root position of the articulations of ``frame``'s envs ``rows`` (in the reference's
    frame); None without articulations."""
    articulations = list(env.scene.articulations.values())
    if not articulations:
        return None
    ids = np.asarray(frame.env_ids)[rows]
    pos = [a.data.root_pos_env.detach().cpu().numpy()[ids].astype(np.float64) for a in articulations]
    return (np.mean(pos, axis=0) + frame.offsets[rows]).mean(axis=0)


def _follow(
    eye: np.ndarray, lookat: np.ndarray, followed: np.ndarray | None, roots: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """The camera (``eye``, ``lookat``) and the point it follows, moved just enough that ``roots`` lie
    within ``FOLLOW`` of its distance from that point."""
    if followed is None or roots is None:
        return eye, lookat, followed
    moved = roots - followed
    off, slack = float(np.linalg.norm(moved)), FOLLOW * float(np.linalg.norm(eye - lookat))
    if off <= slack:
        return eye, lookat, followed
    shift = moved * (1.0 - slack / off)
    return eye + shift, lookat + shift, followed + shift


def _framed_geoms(env) -> tuple[np.ndarray, np.ndarray]:
    """The visible geoms off the world body, split into what the env is about (its articulations: the
    robots, a cabinet) and the rest (objects, props); all of them in the first part if it has no
    articulations."""
    model = env.sim.model
    visible = (model.geom_bodyid > 0) & (model.geom_rgba[:, 3] > 0) & (model.geom_group < 3)
    bodies = [b for asset in env.scene.articulations.values() for b in asset._body_ids]
    subject = visible & np.isin(model.geom_bodyid, bodies)
    if not subject.any():
        return np.flatnonzero(visible), np.zeros(0, dtype=int)
    return np.flatnonzero(subject), np.flatnonzero(visible & ~subject)


def _aim(env, frame: ViewFrame, rows: np.ndarray, resolution: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """The eye and look-at point of ``frame``, turned to the middle of the robots of its envs ``rows``
    and the objects near them (the box of their bounding spheres), at the configured distance or, if
    they fit from nearer, there."""
    import torch

    towards_eye = frame.eye - frame.lookat
    configured = float(np.linalg.norm(towards_eye))
    model = env.sim.model
    subject, others = _framed_geoms(env)
    if len(subject) == 0 or configured < 1e-9:
        return frame.eye, frame.lookat
    ids = np.asarray(frame.env_ids)[rows]
    xpos = env.sim.physics.data("geom_xpos")
    xpos = xpos[torch.as_tensor(ids, device=xpos.device)].reshape(len(ids), model.ngeom, 3)
    xpos = xpos.cpu().numpy().astype(np.float64) + frame.offsets[rows, None]  # the reference's frame
    radii = model.geom_rbound[:, None]
    low, high = (
        (xpos[:, subject] - radii[subject]).min(axis=(0, 1)),
        (xpos[:, subject] + radii[subject]).max(axis=(0, 1)),
    )
    # the objects lying wholly near the robots (what they handle), not the props they stand on nor
    # objects kept far off (the parked instances of a rigid object collection)
    margin = NEAR * float((high - low).max())
    o_low, o_high = xpos[:, others] - radii[others], xpos[:, others] + radii[others]
    near = ((o_low >= low - margin) & (o_high <= high + margin)).all(axis=-1)
    if near.any():
        low, high = np.minimum(low, o_low[near].min(axis=0)), np.maximum(high, o_high[near].max(axis=0))
    lookat = (low + high) / 2
    half_fovy = np.radians(model.vis.global_.fovy) / 2
    half_fovx = np.arctan(np.tan(half_fovy) * resolution[0] / resolution[1])
    fits = float(np.linalg.norm(high - low)) / 2 / np.sin(min(half_fovy, half_fovx))
    return lookat + towards_eye / configured * min(configured, fits), lookat


def renderer_kind(uses_mujoco_warp: bool) -> str:
    """``"opengl"`` (MuJoCo's renderer; it also draws debug markers) where an OpenGL backend works,
    else ``"warp"`` (MuJoCo Warp's ray tracer) for a simulation on MuJoCo Warp. ``SIMLAB_RENDERER``
    = ``opengl`` / ``warp`` picks one; without either, the OpenGL error says what to install."""
    from simlab.utils.gl_backend import GLBackendError, check_gl_backend

    asked = os.environ.get("SIMLAB_RENDERER", "auto").lower()
    if asked not in RENDERERS:
        raise ValueError(f"SIMLAB_RENDERER={asked!r} is not one of {RENDERERS}")
    if asked == "warp" or (asked == "auto" and uses_mujoco_warp and not _gl_works()):
        if not uses_mujoco_warp:
            raise ValueError("SIMLAB_RENDERER=warp renders MuJoCo Warp simulations only (device cuda)")
        return "warp"
    try:
        check_gl_backend()
    except GLBackendError as err:
        raise GLBackendError(f"{err} On a GPU, simlab renders with MuJoCo Warp instead (device cuda).") from err
    return "opengl"


def _gl_works() -> bool:
    from simlab.utils.gl_backend import GLBackendError, check_gl_backend

    try:
        check_gl_backend()
    except GLBackendError:
        return False
    return True


def uses_mujoco_warp(env) -> bool:
    return hasattr(env.sim.physics, "wp_data")


def render_frame(env, viewer) -> np.ndarray:
    """An RGB frame (H, W, 3) of ``env`` from its viewer camera; the renderer is made on first use."""
    renderer = getattr(env, "_renderer", None)
    if renderer is None:
        width, height = viewer.resolution
        if renderer_kind(uses_mujoco_warp(env)) == "warp":
            from simlab.sim.warp_renderer import WarpRenderer

            renderer = WarpRenderer(env.sim.spec, env.sim.physics, width, height, MAX_SHOWN_ENVS)
        else:
            from simlab.sim.renderer import OffscreenRenderer

            renderer = OffscreenRenderer(env.sim.model, width, height, MAX_SHOWN_ENVS)
        env._renderer = renderer
    frame = view_frame(env, viewer, renderer.max_envs)
    return renderer.render(env.sim.physics, frame.env_ids, frame.offsets, frame.eye, frame.lookat)


def close_renderer(env) -> None:
    """Release ``env``'s offscreen renderer and viewer, if it has them."""
    for name in ("_renderer", "_viewer"):
        handle = getattr(env, name, None)
        if handle is not None:
            handle.close()
            setattr(env, name, None)


def show_in_viewer(env) -> None:
    """``render_mode="human"``: show ``env`` in the live viewer the app asked for (``AppLauncher``'s
    ``--viewer``; else native with a display, web without), opened on the first call."""
    viewer = getattr(env, "_viewer", None)
    if viewer is None:
        from simlab.utils.human_viewer import open_human_viewer

        viewer = env._viewer = open_human_viewer(env)
        if viewer is None:
            env._viewer = _NO_VIEWER
            return
    if viewer is not _NO_VIEWER:
        viewer.after_step()


class _NoViewer:
    """Stands for a viewer that could not open (warned once): ``render()`` then does nothing."""

    def close(self) -> None:
        pass


_NO_VIEWER = _NoViewer()
