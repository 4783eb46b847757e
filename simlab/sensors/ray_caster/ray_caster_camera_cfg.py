"""Configuration of the ray-cast camera (Isaac Lab's ``RayCasterCameraCfg``)."""

from __future__ import annotations

from dataclasses import MISSING
from typing import Literal

from simlab.utils import configclass

from .patterns.patterns_cfg import PinholeCameraPatternCfg
from .ray_caster_camera import RayCasterCamera
from .ray_caster_cfg import RayCasterCfg


@configclass
class RayCasterCameraCfg(RayCasterCfg):
    """A depth camera made of rays, one per pixel, cast against static geometry (``mesh_prim_paths``).

    ``prim_path`` names the frame it rides on: a body (``{ENV_REGEX_NS}/Robot/base``) or ``Xform``
    groups made with ``create_prim`` (``/World/Origin_.*/CameraSensor``: one camera, and one world, per
    group)."""

    @configclass
    class OffsetCfg:
        """The camera's pose in the frame it rides on."""

        pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
        rot: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
        """(w, x, y, z), in the frame convention ``convention`` names."""
        convention: Literal["opengl", "ros", "world"] = "ros"
        """``opengl``: forward -z, up +y; ``ros``: forward +z, up -y; ``world``: forward +x, up +z."""

    class_type: type = RayCasterCamera
    offset: OffsetCfg = OffsetCfg()
    data_types: list[str] = ["distance_to_image_plane"]
    """Any of ``distance_to_image_plane``, ``distance_to_camera``, ``normals``."""
    depth_clipping_behavior: Literal["max", "zero", "none"] = "none"
    """Depths beyond ``max_distance`` and misses: ``max`` gives ``max_distance``, ``zero`` 0, ``none``
    leaves them (a miss is ``inf`` in ``distance_to_camera``, ``nan`` in ``distance_to_image_plane``)."""
    pattern_cfg: PinholeCameraPatternCfg = MISSING

    def __post_init__(self):
        self.ray_alignment = "base"  # a camera turns with its frame, always (as in Isaac Lab)
