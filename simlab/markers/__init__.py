"""Debug-visualization markers (Isaac Lab's ``isaaclab.markers``), drawn into offscreen renders.

See :mod:`simlab.markers.visualization_markers` for what is drawn and how.
"""

from .config import (
    BLUE_ARROW_X_MARKER_CFG,
    CONTACT_SENSOR_MARKER_CFG,
    CUBOID_MARKER_CFG,
    FRAME_MARKER_CFG,
    GREEN_ARROW_X_MARKER_CFG,
    POSITION_GOAL_MARKER_CFG,
    RAY_CASTER_MARKER_CFG,
    RED_ARROW_X_MARKER_CFG,
)
from .visualization_markers import ArrowCfg, FrameCfg, VisualizationMarkers, VisualizationMarkersCfg

__all__ = [
    "BLUE_ARROW_X_MARKER_CFG",
    "CONTACT_SENSOR_MARKER_CFG",
    "CUBOID_MARKER_CFG",
    "FRAME_MARKER_CFG",
    "GREEN_ARROW_X_MARKER_CFG",
    "POSITION_GOAL_MARKER_CFG",
    "RAY_CASTER_MARKER_CFG",
    "RED_ARROW_X_MARKER_CFG",
    "ArrowCfg",
    "FrameCfg",
    "VisualizationMarkers",
    "VisualizationMarkersCfg",
]
