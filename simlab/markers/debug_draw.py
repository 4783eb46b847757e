"""Isaac Sim's debug drawing (``isaacsim.util.debug_draw._debug_draw``): lines and points shown in
offscreen renders, videos and the live viewers, like the markers of :mod:`simlab.markers`.

``acquire_debug_draw_interface()`` returns the one drawer of the process, as Isaac Sim's does. What
is drawn stays until cleared. A line is MuJoCo's line geom, its thickness in pixels as Isaac Sim's;
a point is a sphere of 1 mm radius per pixel of its size (MuJoCo draws no screen-sized points).
Colours are RGBA in [0, 1]. Each line and point shows in the env whose origin is nearest to it (its
start, for a line), as markers do.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np
import torch

from simlab.sim.renderer import add_scene_decor

_POINT_RADIUS_PER_PIXEL = 0.001  # [m]


class DebugDraw:
    """Lines and points to draw (Isaac Sim's ``DebugDraw`` interface, the calls its scripts use)."""

    def __init__(self) -> None:
        self._lines = np.zeros((0, 11))  # start (3), end (3), rgba (4), thickness (1)
        self._points = np.zeros((0, 8))  # position (3), rgba (4), size (1)

    def draw_lines(
        self,
        start_point_list: Sequence[Sequence[float]],
        end_point_list: Sequence[Sequence[float]],
        color_list: Sequence[Sequence[float]],
        size_list: Sequence[float],
    ) -> None:
        """Add lines from each start to each end point, with one colour and thickness [px] each."""
        starts, ends = _rows(start_point_list, 3, "start_point_list"), _rows(end_point_list, 3, "end_point_list")
        colors, sizes = _rows(color_list, 4, "color_list"), np.asarray(size_list, dtype=np.float64).reshape(-1, 1)
        _same_count("draw_lines", starts, ends, colors, sizes)
        self._lines = np.concatenate([self._lines, np.hstack([starts, ends, colors, sizes])])

    def draw_points(
        self, point_list: Sequence[Sequence[float]], color_list: Sequence[Sequence[float]], size_list: Sequence[float]
    ) -> None:
        """Add points with one colour and size [px] each."""
        points, colors = _rows(point_list, 3, "point_list"), _rows(color_list, 4, "color_list")
        sizes = np.asarray(size_list, dtype=np.float64).reshape(-1, 1)
        _same_count("draw_points", points, colors, sizes)
        self._points = np.concatenate([self._points, np.hstack([points, colors, sizes])])

    def clear_lines(self) -> None:
        self._lines = self._lines[:0]

    def clear_points(self) -> None:
        self._points = self._points[:0]

    def get_num_lines(self) -> int:
        return len(self._lines)

    def get_num_points(self) -> int:
        return len(self._points)

    def add_to_scene(self, scene: mujoco.MjvScene, env_index: int, env_origins: torch.Tensor | None) -> None:
        """Draw the lines and points that belong to env ``env_index``, in that env's frame (for the renderer)."""
        if not len(self._lines) and not len(self._points):
            return
        origins = None if env_origins is None else env_origins.detach().to("cpu", torch.float64).numpy()
        origin = origins[env_index] if origins is not None and len(origins) else np.zeros(3)
        eye = np.eye(3).reshape(-1)
        for line in self._lines[_in_env(self._lines[:, :3], env_index, origins)]:
            if not _room(scene):
                return
            geom = scene.geoms[scene.ngeom]
            mujoco.mjv_initGeom(geom, mujoco.mjtGeom.mjGEOM_LINE, np.zeros(3), np.zeros(3), eye, line[6:10])
            mujoco.mjv_connector(geom, mujoco.mjtGeom.mjGEOM_LINE, line[10], line[0:3] - origin, line[3:6] - origin)
            scene.ngeom += 1
        for point in self._points[_in_env(self._points[:, :3], env_index, origins)]:
            if not _room(scene):
                return
            size = np.full(3, point[7] * _POINT_RADIUS_PER_PIXEL)
            mujoco.mjv_initGeom(
                scene.geoms[scene.ngeom], mujoco.mjtGeom.mjGEOM_SPHERE, size, point[0:3] - origin, eye, point[3:7]
            )
            scene.ngeom += 1


def _rows(values, width: int, name: str) -> np.ndarray:
    if isinstance(values, torch.Tensor):
        values = values.detach().cpu().numpy()
    rows = np.asarray(values, dtype=np.float64)
    if rows.size == 0:
        return rows.reshape(0, width)
    if rows.ndim != 2 or rows.shape[1] != width:
        raise ValueError(f"{name} must be a list of {width}-element rows, got shape {rows.shape}.")
    return rows


def _same_count(call: str, *lists: np.ndarray) -> None:
    counts = [len(rows) for rows in lists]
    if len(set(counts)) > 1:
        raise ValueError(f"{call}: the lists must be equally long (one entry per item), got lengths {counts}.")


def _in_env(positions: np.ndarray, env_index: int, origins: np.ndarray | None) -> np.ndarray:
    if origins is None or len(origins) <= 1:
        return np.ones(len(positions), dtype=bool)
    return np.argmin(((positions[:, None, :] - origins[None]) ** 2).sum(-1), axis=1) == env_index


def _room(scene: mujoco.MjvScene) -> bool:
    return scene.ngeom < scene.maxgeom  # a full scene drops extra geoms, as MuJoCo does


_INTERFACE = DebugDraw()


def acquire_debug_draw_interface() -> DebugDraw:
    """The process's debug drawer (Isaac Sim's ``_debug_draw.acquire_debug_draw_interface()``)."""
    return _INTERFACE


add_scene_decor(_INTERFACE.add_to_scene)  # the offscreen renderer (a layer below) draws it
