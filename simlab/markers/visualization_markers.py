"""Debug markers (arrows, frames, spheres, boxes) drawn into simlab's offscreen renders.

Isaac Lab draws markers as USD point instancers in the viewport. simlab has no viewport: a
:class:`VisualizationMarkers` keeps the poses last given to :meth:`~VisualizationMarkers.visualize`,
and every offscreen render (``env.render()``, recorded videos) adds the visible markers to the scene
as MuJoCo decor geoms, which have no mass and no contacts. Markers are in the world frame, env
origins included, like asset data; each is drawn in the env whose origin is nearest to it.

Prototypes are simlab's shape configs (:class:`~simlab.sim.SphereCfg`, ``CuboidCfg``, ``CylinderCfg``,
``CapsuleCfg``) or the marker shapes :class:`ArrowCfg` (along +x) and :class:`FrameCfg` (x, y, z axes
in red, green, blue). Isaac Lab's ``arrow_x.usd`` and ``frame_prim.usd`` prototypes, given as
``UsdFileCfg``, are drawn as those; any other USD prototype is refused.
"""

from __future__ import annotations

import os
import weakref
from dataclasses import MISSING
from typing import Any

import mujoco
import numpy as np
import torch

from simlab.sim.renderer import add_scene_decor
from simlab.sim.spawners import CapsuleCfg, CuboidCfg, CylinderCfg, PreviewSurfaceCfg, SphereCfg, UsdFileCfg
from simlab.sim.spawners.from_files.usd_stand_ins import stand_in
from simlab.utils import configclass

__all__ = ["ArrowCfg", "FrameCfg", "VisualizationMarkers", "VisualizationMarkersCfg"]


@configclass
class ArrowCfg:
    """An arrow along the marker's +x axis: ``length`` and shaft ``width`` before ``scale``."""

    length: float = 1.0
    width: float = 0.5
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)
    visual_material: PreviewSurfaceCfg | None = None


@configclass
class FrameCfg:
    """Three arrows along the marker's x, y and z axes (red, green, blue) of ``length`` before ``scale``."""

    length: float = 1.0
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)


@configclass
class VisualizationMarkersCfg:
    """Where the markers live (a name, as in Isaac Lab) and their prototypes by name."""

    prim_path: str = MISSING
    markers: dict[str, Any] = MISSING


# every live marker set, for the renderer to draw (weak: a marker set that is dropped disappears)
_ACTIVE: weakref.WeakSet[VisualizationMarkers] = weakref.WeakSet()

_USD_MARKER_SHAPES = {"arrow_x.usd": "arrow", "frame_prim.usd": "frame"}
_SHAPE_TYPES = (SphereCfg, CuboidCfg, CylinderCfg, CapsuleCfg)
_ARROW_Z_TO_X = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # maps the arrow's z to x
_AXES = (
    (np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]), (0.9, 0.1, 0.1, 1.0)),  # x
    (np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]), (0.1, 0.8, 0.1, 1.0)),  # y
    (np.eye(3), (0.1, 0.2, 0.9, 1.0)),  # z
)


def _rgba(material: PreviewSurfaceCfg | None, default=(0.8, 0.8, 0.8)) -> np.ndarray:
    if material is None:
        return np.array([*default, 1.0])
    return np.array([*material.diffuse_color, material.opacity])


def _prototype(name: str, cfg: Any) -> tuple[str, Any]:
    """``(kind, cfg)`` with kind "shape", "arrow" or "frame"; unsupported prototypes raise."""
    if isinstance(cfg, _SHAPE_TYPES):
        return "shape", cfg
    if isinstance(cfg, ArrowCfg):
        return "arrow", cfg
    if isinstance(cfg, FrameCfg):
        return "frame", cfg
    if isinstance(cfg, UsdFileCfg):
        shape = stand_in(cfg)
        if isinstance(shape, _SHAPE_TYPES):
            return "shape", shape
        kind = _USD_MARKER_SHAPES.get(os.path.basename(str(cfg.usd_path)))
        if kind == "arrow":
            return kind, ArrowCfg(scale=tuple(cfg.scale or (1.0, 1.0, 1.0)), visual_material=cfg.visual_material)
        if kind == "frame":
            return kind, FrameCfg(scale=tuple(cfg.scale or (1.0, 1.0, 1.0)))
    raise ValueError(
        f"Marker prototype '{name}' ({type(cfg).__name__}) cannot be drawn by simlab: use SphereCfg, CuboidCfg,"
        " CylinderCfg, CapsuleCfg, simlab.markers.ArrowCfg or FrameCfg (Isaac Lab's arrow_x.usd,"
        " frame_prim.usd and the USD props of simlab.sim.spawners.from_files.usd_stand_ins are understood)."
    )


class VisualizationMarkers:
    """A set of marker instances, each a copy of one prototype at its own pose and scale."""

    def __init__(self, cfg: VisualizationMarkersCfg):
        if not cfg.markers:
            raise ValueError(f"VisualizationMarkersCfg('{cfg.prim_path}') needs at least one marker prototype.")
        self.cfg = cfg
        self.prim_path = cfg.prim_path
        self._names = list(cfg.markers)
        self._prototypes = [_prototype(name, c) for name, c in cfg.markers.items()]
        self._visible = True
        self._translations = np.zeros((0, 3))
        self._orientations: np.ndarray | None = None
        self._scales: np.ndarray | None = None
        self._indices: np.ndarray | None = None
        _ACTIVE.add(self)

    def __str__(self) -> str:
        names = ", ".join(f"{i}: {n}" for i, n in enumerate(self._names))
        return f"VisualizationMarkers(prim_path={self.prim_path}, count={self.count}, prototypes=[{names}])"

    @property
    def num_prototypes(self) -> int:
        return len(self._prototypes)

    @property
    def count(self) -> int:
        """How many marker instances were last given to :meth:`visualize`."""
        return len(self._translations)

    def set_visibility(self, visible: bool) -> None:
        self._visible = bool(visible)

    def is_visible(self) -> bool:
        return self._visible

    def visualize(
        self,
        translations: torch.Tensor | np.ndarray | None = None,
        orientations: torch.Tensor | np.ndarray | None = None,
        scales: torch.Tensor | np.ndarray | None = None,
        marker_indices: torch.Tensor | np.ndarray | list[int] | None = None,
    ) -> None:
        """Place the markers: positions (M, 3), quaternions (M, 4) ``(w, x, y, z)``, scales (M, 3) and
        the prototype index (M,) of each. What is not given keeps its last value (identity rotation,
        unit scale and prototype 0 at first). Nothing is updated while the markers are hidden.

        Device tensors are kept on their device (a copy, no host sync); they are read back only when
        an image is rendered.
        """
        if not self._visible:
            return
        if translations is not None:
            self._translations = self._as_rows(translations, 3, "translations")
        for name, value, width in (("orientations", orientations, 4), ("scales", scales, 3)):
            if value is not None:
                setattr(self, f"_{name}", self._as_rows(value, width, name))
        if marker_indices is not None:
            indices = marker_indices
            if isinstance(indices, torch.Tensor):
                indices = indices.detach().reshape(-1).clone()
            else:
                indices = np.asarray(indices, dtype=np.int64).reshape(-1)
                self._check_indices(indices)  # host data: check now (device data is checked when drawn)
            self._indices = indices
        for name in ("_orientations", "_scales", "_indices"):
            value = getattr(self, name)
            if value is not None and len(value) != self.count:
                raise ValueError(
                    f"VisualizationMarkers('{self.prim_path}'): {name[1:]} has {len(value)} rows but there are"
                    f" {self.count} markers; give all arrays for the same markers."
                )

    def _check_indices(self, indices: np.ndarray) -> None:
        if len(indices) and (indices.min() < 0 or indices.max() >= self.num_prototypes):
            raise ValueError(
                f"marker_indices must be in [0, {self.num_prototypes - 1}] (prototypes {self._names}),"
                f" got values from {indices.min()} to {indices.max()}."
            )

    @staticmethod
    def _as_rows(value: torch.Tensor | np.ndarray, width: int, name: str) -> torch.Tensor | np.ndarray:
        if not isinstance(value, torch.Tensor):
            value = np.array(value, dtype=np.float64)
        if value.ndim != 2 or value.shape[1] != width:
            raise ValueError(f"{name} must have shape (M, {width}), got {tuple(value.shape)}.")
        return value.detach().clone() if isinstance(value, torch.Tensor) else value

    @staticmethod
    def _host(value: torch.Tensor | np.ndarray | None) -> np.ndarray | None:
        if isinstance(value, torch.Tensor):
            return value.to("cpu", torch.float64 if value.is_floating_point() else torch.int64).numpy()
        return value

    # -- drawing (called by the renderer) ----------------------------------------------------------

    def add_to_scene(self, scene: mujoco.MjvScene, env_index: int, env_origins: np.ndarray | None) -> None:
        """Add this set's markers that belong to env ``env_index`` to ``scene``, in that env's frame."""
        if not self._visible or self.count == 0:
            return
        positions = self._host(self._translations)
        orientations, scales, indices = (self._host(v) for v in (self._orientations, self._scales, self._indices))
        if indices is not None:
            self._check_indices(indices)
        if env_origins is not None and len(env_origins) > 1:
            # each marker belongs to the env whose origin is nearest
            owner = np.argmin(((positions[:, None, :] - env_origins[None]) ** 2).sum(-1), axis=1)
            keep = np.nonzero(owner == env_index)[0]
        else:
            keep = np.arange(self.count)
        origin = env_origins[env_index] if env_origins is not None and len(env_origins) else np.zeros(3)
        for i in keep:
            quat = orientations[i] if orientations is not None else np.array([1.0, 0.0, 0.0, 0.0])
            rot = np.zeros(9)
            mujoco.mju_quat2Mat(rot, quat / max(np.linalg.norm(quat), 1e-12))
            scale = scales[i] if scales is not None else np.ones(3)
            kind, cfg = self._prototypes[int(indices[i]) if indices is not None else 0]
            _draw(scene, kind, cfg, positions[i] - origin, rot.reshape(3, 3), scale)


def _add_geom(scene: mujoco.MjvScene, geom_type, size, pos, mat, rgba) -> None:
    if scene.ngeom >= scene.maxgeom:
        return  # the scene is full: MuJoCo drops extra geoms the same way
    mujoco.mjv_initGeom(
        scene.geoms[scene.ngeom],
        int(geom_type),
        np.asarray(size, dtype=np.float64),
        np.asarray(pos, dtype=np.float64),
        np.asarray(mat, dtype=np.float64).reshape(-1),
        np.asarray(rgba, dtype=np.float32),
    )
    scene.ngeom += 1


def _draw(scene: mujoco.MjvScene, kind: str, cfg: Any, pos: np.ndarray, rot: np.ndarray, scale: np.ndarray) -> None:
    scale = scale * np.asarray(getattr(cfg, "scale", (1.0, 1.0, 1.0)) or (1.0, 1.0, 1.0))
    if kind == "shape":
        size = np.asarray(cfg.geom_size(), dtype=np.float64)
        if isinstance(cfg, SphereCfg):
            size = size * scale[0]
        elif isinstance(cfg, CuboidCfg):
            size = size * scale
        else:  # capsule, cylinder: radius by x, half length by z
            size = size * np.array([scale[0], scale[2], 1.0])
        _add_geom(scene, cfg.geom_type(), size, pos, rot, _rgba(cfg.visual_material))
    elif kind == "arrow":
        length, half_width = cfg.length * scale[0], 0.5 * cfg.width * scale[1]
        _add_geom(
            scene,
            mujoco.mjtGeom.mjGEOM_ARROW,
            (half_width, half_width, length),
            pos,
            rot @ _ARROW_Z_TO_X,
            _rgba(cfg.visual_material, default=(0.9, 0.3, 0.1)),
        )
    else:  # frame
        for axis, (to_axis, rgba) in enumerate(_AXES):
            length = cfg.length * scale[axis]
            _add_geom(
                scene, mujoco.mjtGeom.mjGEOM_ARROW, (0.04 * length, 0.04 * length, length), pos, rot @ to_axis, rgba
            )


def add_markers_to_scene(scene: mujoco.MjvScene, env_index: int, env_origins: torch.Tensor | None) -> None:
    """Draw every live, visible marker set that has markers in env ``env_index`` (for the renderer)."""
    if not _ACTIVE:
        return
    origins = None if env_origins is None else env_origins.detach().to("cpu", torch.float64).numpy()
    for markers in list(_ACTIVE):
        markers.add_to_scene(scene, env_index, origins)


add_scene_decor(add_markers_to_scene)  # the offscreen renderer (a layer below) draws them so
