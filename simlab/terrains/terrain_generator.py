"""The terrain generator: fills a grid of tiles with sub-terrains, seeded and cached by config.

Tile (row, col) covers x in [row, row + 1) * size[0] and y in [col, col + 1) * size[1], shifted so
that the grid is centred on the world origin (as Isaac Lab's). ``terrain_origins[row, col]`` is where
an env on that tile starts.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass

import numpy as np

from simlab.utils.dict import class_to_dict

from .box_terrains import ring
from .height_field import HfTerrainBaseCfg
from .sub_terrain_cfg import SubTerrainBaseCfg, TileGeometry
from .terrain_generator_cfg import TerrainGeneratorCfg


@dataclass
class Tile:
    """One generated tile, in the world frame."""

    row: int
    col: int
    kind: str
    """Name of its sub-terrain in ``TerrainGeneratorCfg.sub_terrains``."""
    difficulty: float
    corner: np.ndarray
    """(2,) world xy of the tile's (x min, y min) corner [m]."""
    geometry: TileGeometry
    """In the tile frame: add ``corner`` to x and y for the world frame."""


class TerrainGenerator:
    """The tiles of ``cfg``, their origins, and the border around them.

    Attributes (Isaac Lab's names where it has them): ``terrain_origins`` (num_rows, num_cols, 3),
    ``tiles``, ``border_boxes`` and ``seed`` (the one used).
    """

    def __init__(self, cfg: TerrainGeneratorCfg, device: str = "cpu"):
        validate(cfg)
        self.cfg = cfg
        self.device = device
        # without a seed of its own, numpy's global state picks it (Isaac Lab's): seeding the env fixes the terrain
        self.seed = int(np.random.get_state()[1][0]) if cfg.seed is None else cfg.seed
        rng = np.random.default_rng(self.seed)
        names = list(cfg.sub_terrains)
        proportions = np.array([cfg.sub_terrains[n].proportion for n in names], dtype=np.float64)
        proportions /= proportions.sum()
        low, high = cfg.difficulty_range
        self.tiles: list[Tile] = []
        self.terrain_origins = np.zeros((cfg.num_rows, cfg.num_cols, 3))
        offset = -0.5 * np.array([cfg.num_rows * cfg.size[0], cfg.num_cols * cfg.size[1]])
        for col in range(cfg.num_cols):
            # curriculum: the columns are split between the kinds by proportion
            col_kind = int(np.searchsorted(np.cumsum(proportions), (col + 0.5) / cfg.num_cols))
            for row in range(cfg.num_rows):
                if cfg.curriculum:
                    kind = min(col_kind, len(names) - 1)
                    difficulty = low + (high - low) * (row + rng.uniform()) / cfg.num_rows
                else:
                    kind = int(rng.choice(len(names), p=proportions))
                    difficulty = rng.uniform(low, high)
                geometry = self._make_tile(names[kind], difficulty, rng)
                corner = offset + np.array([row * cfg.size[0], col * cfg.size[1]])
                self.tiles.append(Tile(row, col, names[kind], difficulty, corner, geometry))
                self.terrain_origins[row, col] = geometry.origin + np.array([*corner, 0.0])
        self.border_boxes = self._border()

    def _make_tile(self, name: str, difficulty: float, rng: np.random.Generator) -> TileGeometry:
        sub_cfg = self.cfg.sub_terrains[name].replace(size=tuple(self.cfg.size))
        if isinstance(sub_cfg, HfTerrainBaseCfg):
            sub_cfg = sub_cfg.replace(
                horizontal_scale=self.cfg.horizontal_scale,
                vertical_scale=self.cfg.vertical_scale,
                slope_threshold=self.cfg.slope_threshold,
            )
        try:
            return sub_cfg.function(difficulty, sub_cfg, rng)
        except ValueError as err:
            raise ValueError(f"TerrainGeneratorCfg.sub_terrains['{name}']: {err}") from err

    def _border(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """Four boxes of flat ground ``border_width`` wide around the grid, top at z = 0."""
        w = self.cfg.border_width
        if w <= 0:
            return []
        inner_x, inner_y = self.cfg.num_rows * self.cfg.size[0], self.cfg.num_cols * self.cfg.size[1]
        return ring(0.0, 0.0, inner_x + 2 * w, inner_y + 2 * w, w, 0.0, -self.cfg.border_height)


def validate(cfg: TerrainGeneratorCfg) -> None:
    """Raise a ValueError naming the setting if ``cfg`` cannot make a terrain."""
    cfg.validate()
    if len(cfg.size) != 2 or min(cfg.size) <= 0:
        raise ValueError(f"TerrainGeneratorCfg.size must be two positive lengths [m], got {cfg.size}")
    if cfg.num_rows < 1 or cfg.num_cols < 1:
        raise ValueError(f"TerrainGeneratorCfg needs num_rows, num_cols >= 1, got {cfg.num_rows}, {cfg.num_cols}")
    if not cfg.sub_terrains:
        raise ValueError("TerrainGeneratorCfg.sub_terrains is empty; give at least one sub-terrain config")
    for name, sub in cfg.sub_terrains.items():
        if not isinstance(sub, SubTerrainBaseCfg):
            raise ValueError(
                f"TerrainGeneratorCfg.sub_terrains['{name}'] is a {type(sub).__name__}, not a sub-terrain config"
            )
        if sub.proportion < 0:
            raise ValueError(
                f"TerrainGeneratorCfg.sub_terrains['{name}'].proportion must be >= 0, got {sub.proportion}"
            )
        if sub.flat_patch_sampling is not None:
            raise ValueError(
                f"TerrainGeneratorCfg.sub_terrains['{name}'].flat_patch_sampling is not supported; set it to None"
            )
    if sum(s.proportion for s in cfg.sub_terrains.values()) <= 0:
        raise ValueError(
            "TerrainGeneratorCfg.sub_terrains' proportions sum to 0; give at least one a positive proportion"
        )
    if cfg.box_tiles_as not in BOX_TILES_AS:
        raise ValueError(f"TerrainGeneratorCfg.box_tiles_as='{cfg.box_tiles_as}' is not one of {BOX_TILES_AS}")
    if cfg.box_height_field_scale is not None and cfg.box_height_field_scale <= 0:
        raise ValueError(
            f"TerrainGeneratorCfg.box_height_field_scale must be > 0 [m] or None, got {cfg.box_height_field_scale}"
        )
    if cfg.horizontal_scale <= 0 or cfg.vertical_scale <= 0:
        raise ValueError(
            f"TerrainGeneratorCfg.horizontal_scale and vertical_scale must be > 0, got"
            f" {cfg.horizontal_scale}, {cfg.vertical_scale}"
        )
    # every tile may become a height field (box tiles too, by default): bound the samples before
    # generating them, rather than fill the host and then the GPU with them
    finest = min(cfg.horizontal_scale, cfg.box_height_field_scale or cfg.horizontal_scale)
    per_tile = (int(cfg.size[0] / finest) + 1) * (int(cfg.size[1] / finest) + 1)
    total = per_tile * cfg.num_rows * cfg.num_cols
    if total > MAX_HEIGHT_SAMPLES:
        raise ValueError(
            f"TerrainGeneratorCfg cannot fit: {cfg.num_rows} x {cfg.num_cols} tiles of {cfg.size} m sampled every"
            f" {finest} m (horizontal_scale / box_height_field_scale) make {total:,} height samples, more than"
            f" {MAX_HEIGHT_SAMPLES:,} (the terrain is in every world's model); raise horizontal_scale, or use"
            " fewer or smaller tiles (num_rows, num_cols, size)"
        )


MAX_HEIGHT_SAMPLES = 50_000_000
"""At most this many height-field samples in a generated terrain (200 MB as float32; Isaac Lab's
ROUGH_TERRAINS_CFG has 1.3 million)."""


BOX_TILES_AS = ("height_field", "boxes")

_CACHE: dict[str, TerrainGenerator] = {}


def config_hash(cfg: TerrainGeneratorCfg) -> str:
    """A digest of everything in ``cfg`` (sub-terrain functions by name)."""
    text = json.dumps(class_to_dict(cfg), sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def generate_terrain(cfg: TerrainGeneratorCfg) -> TerrainGenerator:
    """The terrain of ``cfg``; with a seed, the same config gives the very same (cached) terrain."""
    if cfg.seed is None:
        return TerrainGenerator(cfg)
    key = config_hash(cfg)
    if key not in _CACHE:
        _CACHE[key] = TerrainGenerator(cfg)
    return _CACHE[key]
