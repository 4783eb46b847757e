"""A generated terrain added to a MuJoCo spec: one height field geom per tile, all static in the
world body (the border around the grid is four boxes).

Tiles made of boxes (stairs, box grids) are sampled into height fields by default
(``TerrainGeneratorCfg.box_tiles_as="height_field"``): Isaac Lab's rough preset would otherwise add
~14,000 box geoms, and MuJoCo's collision pass then costs about twice as much per step on the CPU
(docs/terrains.md has the measurement); ``"boxes"`` keeps exact vertical step faces."""

from __future__ import annotations

import mujoco
import numpy as np

from simlab.sim.spawners.materials import MdlFileCfg, PreviewSurfaceCfg, RigidBodyMaterialCfg

from .terrain_generator import TerrainGenerator

HFIELD_BASE_DEPTH = 1.0
"""Thickness of solid ground under a height field's lowest point [m]."""
MIN_ELEVATION_RANGE = 1e-3
"""MuJoCo needs a positive elevation range, even for a flat height field [m]."""


COLOR_SCHEMES = ("none", "height", "random")


def terrain_colors(scheme: str, tops: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """(n, 4) rgba for surfaces whose heights are ``tops`` [m]: Isaac Lab's ``color_scheme``
    ("height": low blue-grey to high sand, "random": a random shade each)."""
    if scheme == "height":
        span = max(float(tops.max() - tops.min()), 1e-6) if len(tops) else 1.0
        t = ((tops - tops.min()) / span)[:, None] if len(tops) else np.zeros((0, 1))
        low, high = np.array([0.25, 0.35, 0.5]), np.array([0.85, 0.75, 0.5])
        return np.hstack([low + t * (high - low), np.ones((len(tops), 1))])
    return np.hstack([rng.uniform(0.3, 0.9, size=(len(tops), 3)), np.ones((len(tops), 1))])


def add_terrain_to_spec(
    spec: mujoco.MjSpec,
    terrain: TerrainGenerator,
    name: str,
    physics_material: RigidBodyMaterialCfg,
    visual_material: PreviewSurfaceCfg | MdlFileCfg | None,
) -> list[mujoco.MjsGeom]:
    rgba = visual_material.rgba() if visual_material is not None else [0.55, 0.55, 0.5, 1.0]
    material = spec.add_material(name=f"{name}/material", rgba=rgba, specular=0.2, shininess=0.2)
    scheme = terrain.cfg.color_scheme
    if scheme not in COLOR_SCHEMES:
        raise ValueError(f"TerrainGeneratorCfg.color_scheme='{scheme}' is not one of {COLOR_SCHEMES}")
    geoms = []

    def add_box(geom_name: str, centre: np.ndarray, size: np.ndarray) -> None:
        geoms.append(
            spec.worldbody.add_geom(
                name=geom_name,
                type=mujoco.mjtGeom.mjGEOM_BOX,
                pos=centre.tolist(),
                size=(size / 2).tolist(),
                friction=physics_material.friction(),
                material=material.name,
            )
        )

    for i, (centre, size) in enumerate(terrain.border_boxes):
        add_box(f"{name}/border_{i}", centre, size)
    tile_geoms_from = len(geoms)
    for tile in terrain.tiles:
        tile_name = f"{name}/tile_{tile.row}_{tile.col}"
        shift = np.array([*tile.corner, 0.0])
        heights = terrain.tile_heights(tile)
        if heights is None or tile.geometry.heights is not None:
            for i, (centre, size) in enumerate(tile.geometry.boxes):
                add_box(f"{tile_name}/box_{i}", centre + shift, size)
        if heights is not None:
            geoms.append(add_height_field(spec, tile_name, heights, shift, terrain.cfg.size))
            geoms[-1].friction = physics_material.friction()
            geoms[-1].material = material.name
    if scheme != "none":
        coloured = geoms[tile_geoms_from:]
        tops = np.array([surface_height(spec, g) for g in coloured])
        for geom, rgba in zip(coloured, terrain_colors(scheme, tops, np.random.default_rng(terrain.seed)), strict=True):
            geom.material, geom.rgba = "", rgba.tolist()
    return geoms


def surface_height(spec: mujoco.MjSpec, geom: mujoco.MjsGeom) -> float:
    """Height of a terrain geom's top (a box's top face, a height field's mean height) [m]."""
    if geom.type == mujoco.mjtGeom.mjGEOM_BOX:
        return float(geom.pos[2] + geom.size[2])
    hfield = spec.hfield(geom.hfieldname)
    return float(geom.pos[2] + np.mean(hfield.userdata) * hfield.size[2])


def add_height_field(
    spec: mujoco.MjSpec, name: str, heights: np.ndarray, corner: np.ndarray, size: tuple[float, float]
) -> mujoco.MjsGeom:
    """``heights`` (indexed [x, y], spanning ``size`` from ``corner``) as a height field geom.

    MuJoCo stores a height field's samples row by row along y (row r at y, column c at x),
    normalised to [0, 1] and scaled by the elevation range; the geom sits at the lowest height.
    """
    low, high = float(heights.min()), float(heights.max())
    elevation = max(high - low, MIN_ELEVATION_RANGE)
    normalised = ((heights - low) / elevation).T  # MuJoCo's rows run along y
    spec.add_hfield(
        name=f"{name}/hfield",
        size=[size[0] / 2, size[1] / 2, elevation, HFIELD_BASE_DEPTH],
        nrow=normalised.shape[0],
        ncol=normalised.shape[1],
        userdata=normalised.astype(np.float32).flatten().tolist(),
    )
    centre = corner + np.array([size[0] / 2, size[1] / 2, low])
    return spec.worldbody.add_geom(
        name=f"{name}/hfield", type=mujoco.mjtGeom.mjGEOM_HFIELD, hfieldname=f"{name}/hfield", pos=centre.tolist()
    )
