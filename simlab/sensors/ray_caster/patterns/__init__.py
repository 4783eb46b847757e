"""Ray patterns of the ray caster (Isaac Lab's ``isaaclab.sensors.patterns``)."""

from .patterns import grid_pattern, lidar_pattern, pinhole_camera_pattern
from .patterns_cfg import GridPatternCfg, LidarPatternCfg, PatternBaseCfg, PinholeCameraPatternCfg

__all__ = [
    "GridPatternCfg",
    "LidarPatternCfg",
    "PatternBaseCfg",
    "PinholeCameraPatternCfg",
    "grid_pattern",
    "lidar_pattern",
    "pinhole_camera_pattern",
]
