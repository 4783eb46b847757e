"""Ray patterns of the ray caster (Isaac Lab's ``isaaclab.sensors.patterns``)."""

from .patterns import grid_pattern, lidar_pattern
from .patterns_cfg import GridPatternCfg, LidarPatternCfg, PatternBaseCfg

__all__ = ["GridPatternCfg", "LidarPatternCfg", "PatternBaseCfg", "grid_pattern", "lidar_pattern"]
