"""Configuration of the frame transformer (Isaac Lab's ``frame_transformer_cfg``)."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.markers import FRAME_MARKER_CFG, VisualizationMarkersCfg
from simlab.utils import configclass

from ..sensor_base import SensorBaseCfg
from .frame_transformer import FrameTransformer


@configclass
class OffsetCfg:
    """A fixed transform from a body's frame to the frame wanted."""

    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rot: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    """Quaternion (w, x, y, z)."""


@configclass
class FrameTransformerCfg(SensorBaseCfg):
    @configclass
    class FrameCfg:
        prim_path: str = MISSING
        """The body (``{ENV_REGEX_NS}/Robot/panda_hand``), an entity's root body, or a regex over bodies."""
        name: str | None = None
        """The frame's name in ``data.target_frame_names`` (default: the body's name)."""
        offset: OffsetCfg = OffsetCfg()

    class_type: type = FrameTransformer
    source_frame_offset: OffsetCfg = OffsetCfg()
    target_frames: list[FrameCfg] = MISSING
    visualizer_cfg: VisualizationMarkersCfg = FRAME_MARKER_CFG.replace(prim_path="/Visuals/FrameTransformer")
    """The markers ``debug_vis`` draws at every target frame (x red, y green, z blue)."""
