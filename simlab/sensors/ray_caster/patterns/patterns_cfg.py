"""Configurations of the ray patterns (Isaac Lab's names and fields)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import MISSING

from simlab.utils import configclass

from . import patterns


@configclass
class PatternBaseCfg:
    func: Callable = MISSING
    """``func(cfg, device) -> (starts (R, 3), directions (R, 3))`` in the sensor's frame."""


@configclass
class GridPatternCfg(PatternBaseCfg):
    """Parallel rays on a 2D grid in the sensor's xy plane (the height scanner's pattern)."""

    func: Callable = patterns.grid_pattern
    resolution: float = MISSING
    """Spacing of the rays [m]."""
    size: tuple[float, float] = MISSING
    """(length along x, width along y) of the grid [m]."""
    direction: tuple[float, float, float] = (0.0, 0.0, -1.0)
    """Direction of every ray (normalised), in the sensor's frame."""
    ordering: str = "xy"
    """"xy": x varies fastest along the rays; "yx": y varies fastest."""


@configclass
class LidarPatternCfg(PatternBaseCfg):
    func: Callable = patterns.lidar_pattern
    channels: int = MISSING
    vertical_fov_range: tuple[float, float] = MISSING
    """Lowest and highest elevation [deg]."""
    horizontal_fov_range: tuple[float, float] = MISSING
    """First and last azimuth [deg]."""
    horizontal_res: float = MISSING
    """Azimuth step [deg]."""
