"""Configuration of the terrain generator: a grid of tiles, rows = difficulty levels, columns = kinds."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.utils import configclass

from .sub_terrain_cfg import SubTerrainBaseCfg


@configclass
class TerrainGeneratorCfg:
    seed: int | None = None
    """Seed of the generator's random draws; None draws one (and the terrain is not cached)."""
    curriculum: bool = False
    """True: row r has difficulty in [r, r+1) / num_rows and each column one sub-terrain kind (by
    proportion). False: every tile draws its kind by proportion and its difficulty uniformly."""
    size: tuple[float, float] = MISSING
    """Size of one tile along x and y [m]."""
    border_width: float = 0.0
    """Width of the flat ground around the whole grid [m]."""
    border_height: float = 1.0
    """Thickness of that border below ground level [m]."""
    num_rows: int = 1
    """Rows along x: the difficulty levels."""
    num_cols: int = 1
    """Columns along y: the sub-terrain kinds."""
    color_scheme: str = "none"
    """"none" (the importer's visual material), "height" (coloured by height) or "random"."""
    horizontal_scale: float = 0.1
    """Spacing of height-field samples [m] (given to every height-field sub-terrain)."""
    vertical_scale: float = 0.005
    """Height resolution of height fields [m]."""
    slope_threshold: float | None = 0.75
    sub_terrains: dict[str, SubTerrainBaseCfg] = MISSING
    box_tiles_as: str = "height_field"
    """simlab's: how tiles made of boxes (stairs, box grids) enter the model: "height_field" (their
    top surface sampled every ``box_height_field_scale`` m; a riser becomes a slope one sample
    wide) or "boxes" (one box geom per box: exact vertical faces, slower collision; see docs/terrains.md)."""
    box_height_field_scale: float | None = None
    """simlab's: sample spacing of box tiles built as height fields [m]; None: ``horizontal_scale``."""
    difficulty_range: tuple[float, float] = (0.0, 1.0)
    use_cache: bool = False
    """Generated terrains are always cached in memory by config (with a seed); kept for Isaac Lab's configs."""
    cache_dir: str = "/tmp/simlab/terrains"
