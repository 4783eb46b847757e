"""The ground surface of generated tiles as the model has it: heights at any point, and a triangle mesh.

A tile enters the model either as a height field (height-field sub-terrains, and box tiles with
``box_tiles_as="height_field"``) or as box geoms (flat tiles, and box tiles with ``box_tiles_as="boxes"``).
Both readings here follow that choice, so flat patches and the mesh describe the ground robots stand on.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .box_terrains import boxes_to_heights
from .sub_terrain_cfg import TileGeometry

if TYPE_CHECKING:
    import trimesh

    from .terrain_generator_cfg import TerrainGeneratorCfg


def box_tile_spacing(cfg: TerrainGeneratorCfg) -> float:
    """Sample spacing of box tiles built as height fields [m]."""
    return cfg.box_height_field_scale or cfg.horizontal_scale


def height_grid(geometry: TileGeometry, cfg: TerrainGeneratorCfg) -> np.ndarray | None:
    """(nx, ny) heights [m] spanning the tile if it enters the model as a height field, else None."""
    if len(geometry.boxes) > 1 and cfg.box_tiles_as == "height_field":  # a flat tile stays one box
        return boxes_to_heights(geometry.boxes, cfg.size, box_tile_spacing(cfg))
    return geometry.heights


def height_at(geometry: TileGeometry, cfg: TerrainGeneratorCfg, heights: np.ndarray | None, x, y) -> np.ndarray:
    """Ground height [m] at tile-frame points (x, y): bilinear between height samples, or the highest
    box top over the point (-inf where nothing is)."""
    x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    if heights is not None:
        return _bilinear(heights, cfg.size, x, y)
    z = np.full(x.shape, -np.inf)
    for centre, full in geometry.boxes:
        inside = (np.abs(x - centre[0]) <= full[0] / 2) & (np.abs(y - centre[1]) <= full[1] / 2)
        z = np.where(inside, np.maximum(z, centre[2] + full[2] / 2), z)
    return z


def _bilinear(heights: np.ndarray, size: tuple[float, float], x: np.ndarray, y: np.ndarray) -> np.ndarray:
    nx, ny = heights.shape
    u = np.clip(x / size[0] * (nx - 1), 0.0, nx - 1)
    v = np.clip(y / size[1] * (ny - 1), 0.0, ny - 1)
    i, j = np.minimum(u.astype(int), nx - 2), np.minimum(v.astype(int), ny - 2)
    fu, fv = u - i, v - j
    return (
        heights[i, j] * (1 - fu) * (1 - fv)
        + heights[i + 1, j] * fu * (1 - fv)
        + heights[i, j + 1] * (1 - fu) * fv
        + heights[i + 1, j + 1] * fu * fv
    )


def grid_mesh(heights: np.ndarray, size: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (nx * ny, 3) and faces (two per cell) of a height grid spanning ``size`` from (0, 0)."""
    nx, ny = heights.shape
    xs, ys = np.meshgrid(np.linspace(0.0, size[0], nx), np.linspace(0.0, size[1], ny), indexing="ij")
    vertices = np.stack([xs, ys, heights], -1).reshape(-1, 3)
    index = np.arange(nx * ny).reshape(nx, ny)
    a, b, c, d = index[:-1, :-1], index[1:, :-1], index[1:, 1:], index[:-1, 1:]
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return vertices, faces


_CORNERS = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
# the 12 outward-facing triangles of a box over _CORNERS (index = 4 * x + 2 * y + z)
_BOX_FACES = np.array(
    [[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
     [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]]
)  # fmt: skip


def boxes_mesh(boxes: list[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and faces of axis-aligned boxes (centre, full size)."""
    if not boxes:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=int)
    centres = np.array([c for c, _ in boxes])
    sizes = np.array([s for _, s in boxes])
    vertices = (centres[:, None, :] + _CORNERS[None] * sizes[:, None, :]).reshape(-1, 3)
    faces = (_BOX_FACES[None] + 8 * np.arange(len(boxes))[:, None, None]).reshape(-1, 3)
    return vertices, faces


def terrain_mesh(
    tiles: list, border_boxes: list[tuple[np.ndarray, np.ndarray]], cfg: TerrainGeneratorCfg, grids: list
) -> trimesh.Trimesh:
    """The whole terrain (tiles and border) as one triangle mesh in the world frame."""
    import trimesh  # a 0.5 s import, only for users of the mesh

    parts = [boxes_mesh(border_boxes)]
    for tile, heights in zip(tiles, grids, strict=True):
        vertices, faces = grid_mesh(heights, cfg.size) if heights is not None else boxes_mesh(tile.geometry.boxes)
        parts.append((vertices + np.array([*tile.corner, 0.0]), faces))
    offsets = np.cumsum([0] + [len(v) for v, _ in parts[:-1]])
    vertices = np.concatenate([v for v, _ in parts])
    faces = np.concatenate([f + o for (_, f), o in zip(parts, offsets, strict=True)])
    return trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
