"""Sub-terrains made of axis-aligned boxes (Isaac Lab's ``Mesh*TerrainCfg``), built as MuJoCo box geoms.

Isaac Lab builds these as triangle meshes of boxes; MuJoCo collides with boxes directly, with exact
vertical step faces. Every box reaches ``BOX_DEPTH`` below the lowest surface of its tile so nothing
can slip underneath.
"""

from __future__ import annotations

import numpy as np

from simlab.utils import configclass

from .sub_terrain_cfg import SubTerrainBaseCfg, TileGeometry, difficulty_lerp

BOX_DEPTH = 1.0
"""How far below the tile's lowest surface the boxes reach [m]."""


def column(x: float, y: float, size_x: float, size_y: float, top: float, bottom: float):
    """A box standing on ``bottom`` with its top at ``top``, centred on (x, y)."""
    return np.array([x, y, (top + bottom) / 2]), np.array([size_x, size_y, top - bottom])


def ring(cx: float, cy: float, outer_x: float, outer_y: float, width: float, top: float, bottom: float):
    """Four boxes forming a square ring ``width`` wide whose outer edge is ``outer_x`` x ``outer_y``."""
    dx, dy = (outer_x - width) / 2, (outer_y - width) / 2
    inner_y = outer_y - 2 * width
    return [
        column(cx, cy + dy, outer_x, width, top, bottom),
        column(cx, cy - dy, outer_x, width, top, bottom),
        column(cx + dx, cy, width, inner_y, top, bottom),
        column(cx - dx, cy, width, inner_y, top, bottom),
    ]


def boxes_to_heights(
    boxes: list[tuple[np.ndarray, np.ndarray]], size: tuple[float, float], spacing: float
) -> np.ndarray:
    """(nx, ny) heights [m], indexed [x, y], of the top surface of ``boxes`` sampled every ``spacing``
    metres over a tile (a sample on the edge between two boxes takes the higher top, so a step's
    tread keeps its full depth and the riser becomes a slope ``spacing`` wide on the lower side)."""
    nx, ny = int(round(size[0] / spacing)) + 1, int(round(size[1] / spacing)) + 1
    xs, ys = np.linspace(0.0, size[0], nx), np.linspace(0.0, size[1], ny)
    heights = np.full((nx, ny), -np.inf)
    tol = 1e-6 * spacing
    for centre, full in boxes:
        in_x = np.abs(xs - centre[0]) <= full[0] / 2 + tol
        in_y = np.abs(ys - centre[1]) <= full[1] / 2 + tol
        if in_x.any() and in_y.any():
            block = np.ix_(in_x, in_y)
            heights[block] = np.maximum(heights[block], centre[2] + full[2] / 2)
    if np.isinf(heights).any():
        raise ValueError("the boxes of a tile leave part of it uncovered; every sample needs a box under it")
    return heights


def flat_terrain(difficulty: float, cfg: MeshPlaneTerrainCfg, rng: np.random.Generator) -> TileGeometry:
    cx, cy = cfg.size[0] / 2, cfg.size[1] / 2
    return TileGeometry(origin=np.array([cx, cy, 0.0]), boxes=[column(cx, cy, *cfg.size, 0.0, -BOX_DEPTH)])


def pyramid_stairs_terrain(
    difficulty: float, cfg: MeshPyramidStairsTerrainCfg, rng: np.random.Generator
) -> TileGeometry:
    """Square rings of steps, ``step_width`` deep and ``step_height_range`` high (by difficulty),
    climbing (or, inverted, descending) from the border at ground level to a platform at the centre."""
    if cfg.holes:
        raise ValueError(f"{type(cfg).__name__}.holes=True is not supported; set holes=False")
    step_height = difficulty_lerp(cfg.step_height_range, difficulty)
    inner = (cfg.size[0] - 2 * cfg.border_width, cfg.size[1] - 2 * cfg.border_width)
    room = min(inner) - cfg.platform_width
    if room < 0 or cfg.step_width <= 0:
        raise ValueError(
            f"{type(cfg).__name__} cannot fit: platform_width={cfg.platform_width} plus 2 x border_width="
            f"{cfg.border_width} must not exceed the tile size {cfg.size}, and step_width={cfg.step_width} must be > 0"
        )
    num_steps = int(room // (2 * cfg.step_width)) + 1
    sign = -1.0 if cfg.inverted else 1.0
    top_of = lambda k: sign * (k + 1) * step_height  # noqa: E731 - ring k from the outside
    bottom = min(0.0, top_of(num_steps)) - BOX_DEPTH
    cx, cy = cfg.size[0] / 2, cfg.size[1] / 2
    boxes = []
    if cfg.border_width > 0:
        boxes += ring(cx, cy, cfg.size[0], cfg.size[1], cfg.border_width, 0.0, bottom)
    for k in range(num_steps):
        outer = (inner[0] - 2 * k * cfg.step_width, inner[1] - 2 * k * cfg.step_width)
        boxes += ring(cx, cy, *outer, cfg.step_width, top_of(k), bottom)
    platform = (inner[0] - 2 * num_steps * cfg.step_width, inner[1] - 2 * num_steps * cfg.step_width)
    boxes.append(column(cx, cy, *platform, top_of(num_steps), bottom))
    return TileGeometry(origin=np.array([cx, cy, top_of(num_steps)]), boxes=boxes)


def random_grid_terrain(difficulty: float, cfg: MeshRandomGridTerrainCfg, rng: np.random.Generator) -> TileGeometry:
    """Square cells ``grid_width`` wide whose tops are drawn uniformly within +-grid_height (by
    difficulty), around a platform ``platform_width`` wide at the centre, ``grid_height`` high."""
    if cfg.size[0] != cfg.size[1]:
        raise ValueError(f"MeshRandomGridTerrainCfg needs square tiles (as Isaac Lab's), got size={cfg.size}")
    if cfg.holes:
        raise ValueError("MeshRandomGridTerrainCfg.holes=True is not supported; set holes=False")
    grid_height = difficulty_lerp(cfg.grid_height_range, difficulty)
    num_cells = int(cfg.size[0] / cfg.grid_width)
    if num_cells < 1 or cfg.platform_width > cfg.size[0]:
        raise ValueError(
            f"MeshRandomGridTerrainCfg cannot fit: grid_width={cfg.grid_width} and platform_width="
            f"{cfg.platform_width} must not exceed the tile size {cfg.size[0]}"
        )
    border = cfg.size[0] - num_cells * cfg.grid_width
    bottom = -grid_height - BOX_DEPTH
    c = cfg.size[0] / 2
    boxes = ring(c, c, cfg.size[0], cfg.size[1], border / 2, 0.0, bottom) if border > 1e-9 else []
    tops = rng.uniform(-grid_height, grid_height, size=(num_cells, num_cells))
    for i in range(num_cells):
        for j in range(num_cells):
            x, y = border / 2 + (i + 0.5) * cfg.grid_width, border / 2 + (j + 0.5) * cfg.grid_width
            boxes.append(column(x, y, cfg.grid_width, cfg.grid_width, tops[i, j], bottom))
    boxes.append(column(c, c, cfg.platform_width, cfg.platform_width, grid_height, bottom))
    return TileGeometry(origin=np.array([c, c, grid_height]), boxes=boxes)


@configclass
class MeshPlaneTerrainCfg(SubTerrainBaseCfg):
    """A flat tile at ground level."""

    function: object = flat_terrain


@configclass
class MeshPyramidStairsTerrainCfg(SubTerrainBaseCfg):
    function: object = pyramid_stairs_terrain
    border_width: float = 0.0
    """Width of the flat band at ground level around the stairs [m]."""
    step_height_range: tuple[float, float] = (0.05, 0.2)
    """Step height at difficulty 0 and 1 [m]."""
    step_width: float = 0.3
    """Depth of each step [m]."""
    platform_width: float = 1.0
    """Side of the square platform at the centre [m]."""
    holes: bool = False
    inverted: bool = False
    """Stairs going down to the centre instead of up."""


@configclass
class MeshInvertedPyramidStairsTerrainCfg(MeshPyramidStairsTerrainCfg):
    inverted: bool = True


@configclass
class MeshRandomGridTerrainCfg(SubTerrainBaseCfg):
    function: object = random_grid_terrain
    grid_width: float = 0.45
    """Side of each cell [m]."""
    grid_height_range: tuple[float, float] = (0.05, 0.2)
    """Largest cell height at difficulty 0 and 1 [m]."""
    platform_width: float = 1.0
    holes: bool = False
