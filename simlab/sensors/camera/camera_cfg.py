"""Configuration of camera sensors (Isaac Lab's ``CameraCfg`` / ``TiledCameraCfg``)."""

from __future__ import annotations

from dataclasses import MISSING
from typing import Literal

from simlab.sim.spawners.sensors import PinholeCameraCfg
from simlab.utils import configclass

from ..sensor_base import SensorBaseCfg
from .camera import DATA_TYPES, Camera, TiledCamera

__all__ = ["DATA_TYPES", "CameraCfg", "TiledCameraCfg"]


@configclass
class CameraCfg(SensorBaseCfg):
    """A camera in every env: on a body (``{ENV_REGEX_NS}/Robot/<body>/<name>``) or fixed in the env
    frame (``{ENV_REGEX_NS}/<name>``), rendering ``data_types`` at ``width`` x ``height``. Under
    ``create_prim`` groups (``/World/Origin_.*/<name>``) one camera at each group."""

    @configclass
    class OffsetCfg:
        """The camera's pose relative to its parent (the body, or the env frame)."""

        pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
        rot: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
        """(w, x, y, z), in the frame convention ``convention`` names."""
        convention: Literal["opengl", "ros", "world"] = "ros"
        """``opengl``: forward -z, up +y; ``ros``: forward +z, up -y; ``world``: forward +x, up +z."""

    class_type: type = Camera
    offset: OffsetCfg = OffsetCfg()
    spawn: PinholeCameraCfg | None = PinholeCameraCfg()
    """The lens; None is refused (simlab has no existing camera prims to wrap)."""
    data_types: list[str] = ["rgb"]
    width: int = MISSING
    height: int = MISSING
    depth_clipping_behavior: Literal["max", "zero", "none"] = "none"
    """Depth where nothing is hit or beyond the far clipping distance: ``none`` gives inf, ``max`` the far
    distance, ``zero`` 0."""
    colorize_semantic_segmentation: bool = True
    """True: ``semantic_segmentation`` is uint8 RGBA colours (N, H, W, 4); False: int32 body ids (N, H, W, 1),
    -1 where nothing is hit. ``data.info[camera]["semantic_segmentation"]["idToLabels"]`` names the bodies."""
    update_latest_camera_pose: bool = False
    semantic_filter: str | list[str] = "*:*"
    colorize_instance_segmentation: bool = True
    """``instance_segmentation_fast`` (one instance per body) as RGBA colours, or int32 body ids."""
    colorize_instance_id_segmentation: bool = True
    """``instance_id_segmentation_fast`` (one instance per geom) as RGBA colours, or int32 geom ids."""
    renderer_cfg: object | None = None
    """Accepted; the renderer follows the device (MuJoCo's OpenGL on the CPU, MuJoCo Warp's on the GPU)."""


@configclass
class TiledCameraCfg(CameraCfg):
    """Isaac Lab's tiled camera: all envs' images in one batched render. simlab's cameras always render
    in batch, so it is the same sensor as :class:`CameraCfg`."""

    class_type: type = TiledCamera
