"""The terrain generator: fills a grid of tiles with sub-terrains, seeded and cached by config.

Tile (row, col) covers x in [row, row + 1) * size[0] and y in [col, col + 1) * size[1], shifted so
that the grid is centred on the world origin (as Isaac Lab's). ``terrain_origins[row, col]`` is where
an env on that tile starts; ``flat_patches[name][row, col]`` are the flat spots found on it (world frame).

With ``cfg.use_cache`` the generated tiles are also written to ``cfg.cache_dir`` (one file per config,
seed included) and read back by later runs instead of generated again.
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
import torch

from simlab.utils.dict import class_to_dict

from .box_terrains import ring
from .flat_patches import check_cfg, find_flat_patches
from .height_field import HfTerrainBaseCfg
from .sub_terrain_cfg import SubTerrainBaseCfg, TileGeometry
from .terrain_generator_cfg import TerrainGeneratorCfg
from .tile_surface import height_at, height_grid, terrain_mesh

if TYPE_CHECKING:
    import trimesh


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
    ``flat_patches`` (name -> (num_rows, num_cols, num_patches, 3) world points), ``terrain_mesh`` (a
    trimesh of the whole terrain, built when first read), ``tiles``, ``border_boxes`` and ``seed``.
    """

    def __init__(self, cfg: TerrainGeneratorCfg, device: str = "cpu"):
        validate(cfg)
        self.cfg = cfg
        self.device = device
        # without a seed of its own, numpy's global state picks it (Isaac Lab's): seeding the env fixes the terrain
        self.seed = int(np.random.get_state()[1][0]) if cfg.seed is None else cfg.seed
        self.terrain_origins = np.zeros((cfg.num_rows, cfg.num_cols, 3))
        cache_file = os.path.join(cfg.cache_dir, f"{config_hash(cfg.replace(seed=self.seed))}.npz")
        if cfg.use_cache and os.path.exists(cache_file):
            self.tiles = load_tiles(cache_file)
        else:
            self.tiles = self._generate_tiles()
            if cfg.use_cache:
                save_tiles(cache_file, self.tiles)
        for tile in self.tiles:
            self.terrain_origins[tile.row, tile.col] = tile.geometry.origin + np.array([*tile.corner, 0.0])
        self.border_boxes = self._border()
        self._height_grids: dict[tuple[int, int], np.ndarray | None] = {}
        self.flat_patches: dict[str, torch.Tensor] = self._find_flat_patches()

    def _generate_tiles(self) -> list[Tile]:
        cfg = self.cfg
        rng = np.random.default_rng(self.seed)
        names = list(cfg.sub_terrains)
        proportions = np.array([cfg.sub_terrains[n].proportion for n in names], dtype=np.float64)
        proportions /= proportions.sum()
        low, high = cfg.difficulty_range
        tiles = []
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
                tiles.append(Tile(row, col, names[kind], difficulty, corner, geometry))
        return tiles

    def tile_heights(self, tile: Tile) -> np.ndarray | None:
        """(nx, ny) heights of ``tile`` as the model holds it, or None for a tile of box geoms."""
        key = (tile.row, tile.col)
        if key not in self._height_grids:
            self._height_grids[key] = height_grid(tile.geometry, self.cfg)
        return self._height_grids[key]

    def _find_flat_patches(self) -> dict[str, torch.Tensor]:
        """Isaac Lab's ``flat_patches``: for each name, (num_rows, num_cols, num_patches, 3) world points.

        A tile whose sub-terrain does not sample patches of a name gets its origin in every slot, so
        that any slot is a place to stand (Isaac Lab leaves zeros there)."""
        wanted: dict[str, int] = {}
        for sub in self.cfg.sub_terrains.values():
            for name, patch_cfg in (sub.flat_patch_sampling or {}).items():
                wanted[name] = max(wanted.get(name, 0), int(patch_cfg.num_patches))
        patches = {name: np.zeros((self.cfg.num_rows, self.cfg.num_cols, n, 3)) for name, n in wanted.items()}
        if not wanted:
            return {}
        rng = np.random.default_rng(np.random.SeedSequence(self.seed & 0xFFFFFFFFFFFFFFFF, spawn_key=(1,)))
        for tile in self.tiles:
            shift = np.array([*tile.corner, 0.0])
            sampling = self.cfg.sub_terrains[tile.kind].flat_patch_sampling or {}
            heights = self.tile_heights(tile)
            surface = lambda x, y, t=tile, h=heights: height_at(t.geometry, self.cfg, h, x, y)  # noqa: E731
            for name, slots in patches.items():
                if name not in sampling:
                    slots[tile.row, tile.col] = tile.geometry.origin + shift
                    continue
                where = f"TerrainGeneratorCfg.sub_terrains['{tile.kind}'].flat_patch_sampling['{name}'] on tile" \
                    f" (row {tile.row}, col {tile.col})"  # fmt: skip
                found = find_flat_patches(surface, self.cfg.size, tile.geometry.origin, sampling[name], rng, where)
                # a sub-terrain asking for fewer patches than another repeats its own to fill the slots
                slots[tile.row, tile.col] = found[np.arange(len(slots[tile.row, tile.col])) % len(found)] + shift
        return {name: torch.tensor(p, dtype=torch.float32, device=self.device) for name, p in patches.items()}

    @cached_property
    def terrain_mesh(self) -> trimesh.Trimesh:
        """Isaac Lab's ``terrain_mesh``: the whole terrain (tiles and border) as one trimesh, world frame."""
        return terrain_mesh(self.tiles, self.border_boxes, self.cfg, [self.tile_heights(t) for t in self.tiles])

    def __str__(self) -> str:
        cfg = self.cfg
        lines = [
            "Terrain Generator:",
            f"\tSeed: {self.seed}" + (" (drawn from numpy's global state)" if cfg.seed is None else ""),
            f"\tNumber of rows: {cfg.num_rows}",
            f"\tNumber of columns: {cfg.num_cols}",
            f"\tSub-terrain size: {tuple(cfg.size)}",
            f"\tSub-terrain types: {list(cfg.sub_terrains)}",
            f"\tCurriculum: {cfg.curriculum}",
            f"\tDifficulty range: {tuple(cfg.difficulty_range)}",
            f"\tColor scheme: {cfg.color_scheme}",
            f"\tUse cache: {cfg.use_cache}" + (f" ({cfg.cache_dir})" if cfg.use_cache else ""),
            f"\tFlat patches: {({n: tuple(p.shape) for n, p in self.flat_patches.items()}) or 'none'}",
        ]
        return "\n".join(lines)

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
            if not isinstance(sub.flat_patch_sampling, dict):
                raise ValueError(
                    f"TerrainGeneratorCfg.sub_terrains['{name}'].flat_patch_sampling must be a dict of"
                    f" name -> FlatPatchSamplingCfg or None, got {type(sub.flat_patch_sampling).__name__}"
                )
            for patch_name, patch_cfg in sub.flat_patch_sampling.items():
                check_cfg(patch_cfg, f"TerrainGeneratorCfg.sub_terrains['{name}'].flat_patch_sampling['{patch_name}']")
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
    """A digest of everything in ``cfg`` that shapes the terrain (sub-terrain functions by name)."""
    shaping = {k: v for k, v in class_to_dict(cfg).items() if k not in ("use_cache", "cache_dir")}
    text = json.dumps(shaping, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def generate_terrain(cfg: TerrainGeneratorCfg) -> TerrainGenerator:
    """The terrain of ``cfg``; with a seed, the same config gives the very same (cached) terrain."""
    if cfg.seed is None:
        return TerrainGenerator(cfg)
    key = config_hash(cfg)
    if key not in _CACHE:
        _CACHE[key] = TerrainGenerator(cfg)
    return _CACHE[key]


def save_tiles(path: str, tiles: list[Tile]) -> None:
    """Write ``tiles`` to ``path`` (.npz of plain arrays; written to a temporary name, then moved)."""
    arrays: dict[str, np.ndarray] = {}
    meta = []
    for i, tile in enumerate(tiles):
        meta.append({"row": tile.row, "col": tile.col, "kind": tile.kind, "difficulty": tile.difficulty})
        arrays[f"corner_{i}"] = tile.corner
        arrays[f"origin_{i}"] = tile.geometry.origin
        arrays[f"boxes_{i}"] = np.array([np.stack(b) for b in tile.geometry.boxes]).reshape(-1, 2, 3)
        if tile.geometry.heights is not None:
            arrays[f"heights_{i}"] = tile.geometry.heights
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    partial = f"{path}.{os.getpid()}.partial.npz"
    np.savez(partial, meta=np.array(json.dumps(meta)), **arrays)
    os.replace(partial, path)


def load_tiles(path: str) -> list[Tile]:
    """The tiles :func:`save_tiles` wrote to ``path``."""
    with np.load(path, allow_pickle=False) as data:
        tiles = []
        for i, m in enumerate(json.loads(str(data["meta"]))):
            geometry = TileGeometry(
                origin=data[f"origin_{i}"],
                heights=data.get(f"heights_{i}"),
                boxes=[(b[0], b[1]) for b in data[f"boxes_{i}"]],
            )
            tiles.append(Tile(m["row"], m["col"], m["kind"], m["difficulty"], data[f"corner_{i}"], geometry))
    return tiles
