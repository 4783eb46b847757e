"""Height-field sub-terrains (Isaac Lab's ``Hf*TerrainCfg``), built as MuJoCo height fields.

Heights are sampled every ``horizontal_scale`` metres over the whole tile and rounded to multiples
of ``vertical_scale`` (as Isaac Lab's int16 height fields are). A border of ``border_width`` around
the tile stays at ground level so neighbouring tiles meet without a step.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from simlab.utils import configclass

from .sub_terrain_cfg import SubTerrainBaseCfg, TileGeometry, difficulty_lerp

ORIGIN_PATCH_HALF_WIDTH = 1.0
"""An env starts on the highest point of the 2 m x 2 m patch at the tile centre (Isaac Lab's rule)."""


def samples(length: float, spacing: float) -> int:
    """How many samples, ``spacing`` apart, span ``length`` end to end."""
    return int(round(length / spacing)) + 1


def height_field_tile(cfg: HfTerrainBaseCfg, interior: Callable[[int, int], np.ndarray]) -> TileGeometry:
    """A tile whose interior (inside the border) has the heights ``interior(nx, ny)`` returns [m]."""
    nx, ny = samples(cfg.size[0], cfg.horizontal_scale), samples(cfg.size[1], cfg.horizontal_scale)
    border = int(round(cfg.border_width / cfg.horizontal_scale))
    if nx - 2 * border < 2 or ny - 2 * border < 2:
        raise ValueError(
            f"{type(cfg).__name__}.border_width={cfg.border_width} leaves no room on a {cfg.size} m tile;"
            f" it must be less than half the tile size"
        )
    heights = np.zeros((nx, ny))
    heights[border : nx - border, border : ny - border] = interior(nx - 2 * border, ny - 2 * border)
    heights = np.round(heights / cfg.vertical_scale) * cfg.vertical_scale
    centre = np.array([cfg.size[0] / 2, cfg.size[1] / 2])
    lo = np.floor((centre - ORIGIN_PATCH_HALF_WIDTH) / cfg.horizontal_scale).astype(int).clip(0)
    hi = np.ceil((centre + ORIGIN_PATCH_HALF_WIDTH) / cfg.horizontal_scale).astype(int) + 1
    origin_z = heights[lo[0] : hi[0], lo[1] : hi[1]].max()
    return TileGeometry(origin=np.array([*centre, origin_z]), heights=heights)


def random_uniform_terrain(difficulty: float, cfg: HfRandomUniformTerrainCfg, rng: np.random.Generator) -> TileGeometry:
    """Heights drawn uniformly from ``noise_range`` in steps of ``noise_step`` (difficulty unused, as in
    Isaac Lab), on a grid ``downsampled_scale`` apart and interpolated to the tile's samples."""
    if cfg.noise_step <= 0 or cfg.noise_range[1] < cfg.noise_range[0]:
        raise ValueError(
            f"HfRandomUniformTerrainCfg needs noise_range=(low, high) with low <= high and noise_step > 0,"
            f" got noise_range={cfg.noise_range}, noise_step={cfg.noise_step}"
        )
    levels = np.arange(cfg.noise_range[0], cfg.noise_range[1] + cfg.noise_step / 2, cfg.noise_step)
    coarse_scale = cfg.downsampled_scale or cfg.horizontal_scale
    if coarse_scale < cfg.horizontal_scale:
        raise ValueError(
            f"HfRandomUniformTerrainCfg.downsampled_scale={coarse_scale} must be at least horizontal_scale="
            f"{cfg.horizontal_scale}"
        )

    def interior(nx: int, ny: int) -> np.ndarray:
        ratio = coarse_scale / cfg.horizontal_scale
        coarse = rng.choice(levels, size=(max(2, round(nx / ratio)), max(2, round(ny / ratio))))
        if coarse.shape == (nx, ny):
            return coarse
        from scipy.ndimage import zoom  # 1 s to import; only rough terrains need it

        return zoom(coarse, (nx / coarse.shape[0], ny / coarse.shape[1]), order=1, grid_mode=False)[:nx, :ny]

    return height_field_tile(cfg, interior)


def pyramid_sloped_terrain(difficulty: float, cfg: HfPyramidSlopedTerrainCfg, rng: np.random.Generator) -> TileGeometry:
    """A four-sided pyramid rising (or, inverted, sinking) with slope ``slope_range`` (rise over run,
    by difficulty) from the border to a flat square platform ``platform_width`` wide at the centre."""
    slope = difficulty_lerp(cfg.slope_range, difficulty) * (-1.0 if cfg.inverted else 1.0)
    h = cfg.horizontal_scale

    def interior(nx: int, ny: int) -> np.ndarray:
        # distance to the interior's nearest edge along x and y; a pyramid rises with the smaller one
        to_edge_x = np.minimum(np.arange(nx), np.arange(nx)[::-1]) * h
        to_edge_y = np.minimum(np.arange(ny), np.arange(ny)[::-1]) * h
        to_edge = np.minimum(to_edge_x[:, None], to_edge_y[None, :])
        platform_edge = min(nx - 1, ny - 1) * h / 2 - cfg.platform_width / 2
        if platform_edge < 0:
            raise ValueError(
                f"{type(cfg).__name__}.platform_width={cfg.platform_width} is wider than the tile's interior"
                f" ({min(nx - 1, ny - 1) * h:.2f} m); make it smaller or the tile larger"
            )
        return slope * np.minimum(to_edge, platform_edge)

    return height_field_tile(cfg, interior)


@configclass
class HfTerrainBaseCfg(SubTerrainBaseCfg):
    border_width: float = 0.0
    """Width of the flat band at ground level around the tile [m]."""
    horizontal_scale: float = 0.1
    """Spacing of the height samples [m]; set by the terrain generator."""
    vertical_scale: float = 0.005
    """Height resolution [m]; set by the terrain generator."""
    slope_threshold: float | None = None
    """Isaac Lab turns slopes steeper than this into vertical walls when meshing; MuJoCo's height
    field interpolates between samples instead, so this is accepted and unused."""


@configclass
class HfRandomUniformTerrainCfg(HfTerrainBaseCfg):
    function: object = random_uniform_terrain
    noise_range: tuple[float, float] = (0.0, 0.1)
    """Lowest and highest height [m]."""
    noise_step: float = 0.005
    """Heights are multiples of this [m]."""
    downsampled_scale: float | None = None
    """Spacing of the random samples before interpolation [m]; None: ``horizontal_scale``."""


@configclass
class HfPyramidSlopedTerrainCfg(HfTerrainBaseCfg):
    function: object = pyramid_sloped_terrain
    slope_range: tuple[float, float] = (0.0, 0.4)
    """Slope (rise over run) at difficulty 0 and 1."""
    platform_width: float = 1.0
    """Side of the flat square at the centre [m]."""
    inverted: bool = False
    """A pit sinking towards the centre instead of a pyramid."""


@configclass
class HfInvertedPyramidSlopedTerrainCfg(HfPyramidSlopedTerrainCfg):
    inverted: bool = True
