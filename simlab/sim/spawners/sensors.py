"""Camera spawners: a pinhole camera becomes an MJCF ``<camera>`` on a body or in the env frame.

MuJoCo cameras look along their -z axis with +y up (the "opengl" convention of Isaac Lab's
cameras), and take a vertical field of view. A pinhole camera's lens (focal length and apertures,
in millimetres as in USD) sets that field of view: ``fovy = 2 atan(vertical_aperture / 2 f)``,
with the vertical aperture following the image's aspect ratio (square pixels) unless given.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Literal

import mujoco

from simlab.utils import configclass

from ..simulation_context import current_spec
from .spawner_cfg import SpawnerCfg


def vertical_aperture(cfg: PinholeCameraCfg, width: int, height: int) -> float:
    """The sensor's height (mm): the config's, else the horizontal aperture scaled by the image's aspect ratio."""
    if cfg.vertical_aperture is not None:
        return float(cfg.vertical_aperture)
    return float(cfg.horizontal_aperture) * height / width


def vertical_fov_degrees(cfg: PinholeCameraCfg, width: int, height: int) -> float:
    """MuJoCo's ``fovy`` (degrees) of a pinhole camera rendering ``width`` x ``height`` images."""
    return math.degrees(2.0 * math.atan(0.5 * vertical_aperture(cfg, width, height) / cfg.focal_length))


def spawn_camera(
    prim_path: str,
    cfg: PinholeCameraCfg,
    translation: Sequence[float] | None = None,
    orientation: Sequence[float] | None = None,
    resolution: tuple[int, int] = (640, 480),
    body: str | None = None,
) -> mujoco.MjsCamera:
    """Add an MJCF camera named after the prim path's last element to ``body`` (None: the env frame).

    ``orientation`` is the camera's (w, x, y, z) rotation in the OpenGL convention (MuJoCo's),
    relative to the body; ``resolution`` is (width, height) in pixels.
    """
    check_pinhole_cfg(cfg)
    spec = current_spec()
    parent = spec.worldbody if body is None else spec.body(body)
    if parent is None:
        raise ValueError(f"Camera '{prim_path}': the model has no body '{body}'")
    name = prim_path.rstrip("/").split("/")[-1]
    if spec.camera(name) is not None:
        raise ValueError(f"Camera '{prim_path}': the model already has a camera named '{name}'; name each camera once")
    width, height = resolution
    return parent.add_camera(
        name=name,
        pos=list(translation) if translation is not None else [0.0, 0.0, 0.0],
        quat=list(orientation) if orientation is not None else [1.0, 0.0, 0.0, 0.0],
        fovy=vertical_fov_degrees(cfg, width, height),
        resolution=[width, height],
    )


def check_pinhole_cfg(cfg: PinholeCameraCfg) -> None:
    """Errors for lens settings simlab's renderers cannot honour."""
    if cfg.projection_type != "pinhole":
        raise ValueError(f"PinholeCameraCfg.projection_type must be 'pinhole', got {cfg.projection_type!r}")
    if not cfg.focal_length > 0 or not cfg.horizontal_aperture > 0:
        raise ValueError(
            "PinholeCameraCfg.focal_length and horizontal_aperture must be positive (millimetres), got"
            f" {cfg.focal_length} and {cfg.horizontal_aperture}"
        )
    near, far = cfg.clipping_range
    if not 0 < near < far:
        raise ValueError(
            f"PinholeCameraCfg.clipping_range must be (near, far) with 0 < near < far, got {cfg.clipping_range}"
        )
    if cfg.f_stop:
        raise ValueError(
            f"PinholeCameraCfg.f_stop={cfg.f_stop} asks for depth of field, which simlab's renderers do not draw"
            " (everything is in focus); leave f_stop at 0"
        )
    if cfg.horizontal_aperture_offset or cfg.vertical_aperture_offset:
        raise ValueError(
            "PinholeCameraCfg aperture offsets (an off-centre principal point) are not supported by simlab's"
            " renderers; leave horizontal_aperture_offset and vertical_aperture_offset at 0"
        )


@configclass
class PinholeCameraCfg(SpawnerCfg):
    """A pinhole camera (Isaac Lab's ``sim_utils.PinholeCameraCfg``); lengths of the lens in mm."""

    func: object = spawn_camera
    projection_type: Literal["pinhole"] = "pinhole"
    clipping_range: tuple[float, float] = (0.01, 1.0e6)
    """Near and far distances (m): depth beyond ``far`` counts as no hit (see ``depth_clipping_behavior``)."""
    focal_length: float = 24.0
    focus_distance: float = 400.0
    """Accepted; MuJoCo's renderers draw everything in focus (no depth of field)."""
    f_stop: float = 0.0
    """0 (no depth of field): other values are refused."""
    horizontal_aperture: float = 20.955
    vertical_aperture: float | None = None
    """None: the horizontal aperture times height / width (square pixels)."""
    horizontal_aperture_offset: float = 0.0
    vertical_aperture_offset: float = 0.0
    lock_camera: bool = True
