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


@configclass
class PinholeCameraPatternCfg(PatternBaseCfg):
    """A ray per pixel of a pinhole camera (the ray-caster camera's pattern). Lengths are in tenths of
    the world unit (cm), as in Isaac Lab and USD cameras; only their ratios matter."""

    func: Callable = patterns.pinhole_camera_pattern
    focal_length: float = 24.0
    """[cm]; longer: narrower field of view."""
    horizontal_aperture: float = 20.955
    """Width of the film [cm]."""
    vertical_aperture: float | None = None
    """Height of the film [cm]; None: from the image's aspect ratio (square pixels)."""
    horizontal_aperture_offset: float = 0.0
    """Shift of the principal point, in units of the focal length over the pixel width (Isaac Lab's rule)."""
    vertical_aperture_offset: float = 0.0
    width: int = MISSING
    """[pixels]"""
    height: int = MISSING
    """[pixels]"""

    def intrinsic_matrix(self) -> list[list[float]]:
        """[[fx, 0, cx], [0, fy, cy], [0, 0, 1]] in pixels, from the lens and the resolution."""
        for name in ("width", "height"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise ValueError(f"PinholeCameraPatternCfg.{name} must be a positive number of pixels, got {value!r}")
        for name in ("focal_length", "horizontal_aperture"):
            if not getattr(self, name) > 0:
                raise ValueError(f"PinholeCameraPatternCfg.{name} must be > 0 [cm], got {getattr(self, name)}")
        vertical = self.vertical_aperture
        if vertical is None:
            vertical = self.horizontal_aperture * self.height / self.width
        elif not vertical > 0:
            raise ValueError(f"PinholeCameraPatternCfg.vertical_aperture must be > 0 [cm] or None, got {vertical}")
        fx = self.width * self.focal_length / self.horizontal_aperture
        fy = self.height * self.focal_length / vertical
        cx = self.horizontal_aperture_offset * fx + self.width / 2
        cy = self.vertical_aperture_offset * fy + self.height / 2
        return [[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]]
