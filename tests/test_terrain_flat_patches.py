"""Flat patches, the terrain mesh and the on-disk terrain cache, checked against the compiled MuJoCo
model: a ray cast straight down onto the terrain geoms is the ground truth for heights."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
import torch

from simlab.sim.spawners.materials import RigidBodyMaterialCfg
from simlab.terrains import (
    FlatPatchSamplingCfg,
    HfPyramidSlopedTerrainCfg,
    HfRandomUniformTerrainCfg,
    MeshPlaneTerrainCfg,
    MeshPyramidStairsTerrainCfg,
    TerrainGenerator,
    TerrainGeneratorCfg,
)
from simlab.terrains.mjspec_terrain import add_terrain_to_spec

TILE = 3.0
RADIUS = 0.2
MAX_DIFF = 0.01


def patchy_terrain(box_tiles_as: str = "height_field", **kw) -> TerrainGeneratorCfg:
    """A slope, stairs, rough ground and a flat tile, each asking for flat patches."""
    spots = {"spawn": FlatPatchSamplingCfg(num_patches=6, patch_radius=RADIUS, max_height_diff=MAX_DIFF)}
    cfg = TerrainGeneratorCfg(
        seed=5,
        curriculum=True,
        size=(TILE, TILE),
        border_width=1.0,
        num_rows=2,
        num_cols=4,
        box_tiles_as=box_tiles_as,
        sub_terrains={
            "slope": HfPyramidSlopedTerrainCfg(
                slope_range=(0.3, 0.4), platform_width=1.2, border_width=0.0, flat_patch_sampling=spots
            ),
            "stairs": MeshPyramidStairsTerrainCfg(
                step_height_range=(0.1, 0.15),
                step_width=0.6,
                platform_width=1.0,
                border_width=0.2,
                flat_patch_sampling=spots,
            ),
            "rough": HfRandomUniformTerrainCfg(noise_range=(0.0, 0.1), noise_step=0.05, border_width=0.3),
            "flat": MeshPlaneTerrainCfg(flat_patch_sampling=spots),
        },
    )
    return cfg.replace(**kw)


def compiled_ground(terrain: TerrainGenerator) -> tuple[mujoco.MjModel, mujoco.MjData]:
    spec = mujoco.MjSpec()
    add_terrain_to_spec(spec, terrain, "ground", RigidBodyMaterialCfg(), None)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def ground_height(model: mujoco.MjModel, data: mujoco.MjData, x: float, y: float) -> float:
    """Height where a ray cast down from 10 m at (x, y) first hits the model."""
    geom = np.zeros(1, dtype=np.int32)
    distance = mujoco.mj_ray(model, data, np.array([x, y, 10.0]), np.array([0.0, 0.0, -1.0]), None, 1, -1, geom)
    assert distance >= 0, f"nothing below ({x}, {y})"
    return 10.0 - distance


@pytest.mark.parametrize("box_tiles_as", ["height_field", "boxes"])
def test_flat_patches_are_flat_in_the_model(box_tiles_as):
    terrain = TerrainGenerator(patchy_terrain(box_tiles_as))
    model, data = compiled_ground(terrain)
    patches = terrain.flat_patches["spawn"]
    assert patches.shape == (2, 4, 6, 3) and patches.dtype == torch.float32
    # Isaac Lab's rule: 10 points on the rim (here also the centre) lie within MAX_DIFF of each other
    angles = np.linspace(0, 2 * np.pi, 10, endpoint=False)
    ring = np.concatenate([[[0.0, 0.0]], RADIUS * np.stack([np.cos(angles), np.sin(angles)], -1)])
    slack = 0.005  # heights between samples interpolate differently in MuJoCo's triangles and here
    for tile in terrain.tiles:
        low = tile.corner
        for x, y, z in patches[tile.row, tile.col].tolist():
            assert low[0] <= x <= low[0] + TILE and low[1] <= y <= low[1] + TILE, "a patch left its tile"
            if tile.kind == "rough":  # no sampling asked: the slot holds the tile's origin
                assert [x, y, z] == pytest.approx(terrain.terrain_origins[tile.row, tile.col].tolist())
                continue
            assert ground_height(model, data, x, y) == pytest.approx(z, abs=slack)
            heights = [ground_height(model, data, x + dx, y + dy) for dx, dy in ring]
            assert max(heights) - min(heights) <= MAX_DIFF + slack, f"{tile.kind} patch at ({x}, {y}) not flat"


def test_patches_on_a_slope_lie_on_its_platform():
    """On a 0.3-0.4 slope, rim points 0.2 m out stay within 1 cm of each other only on the platform."""
    terrain = TerrainGenerator(patchy_terrain())
    for tile in (t for t in terrain.tiles if t.kind == "slope"):
        centre = tile.corner + TILE / 2
        offsets = terrain.flat_patches["spawn"][tile.row, tile.col, :, :2].numpy() - centre
        # the rim points must fit on the 1.2 m platform (the nearest to an edge is r sin 72 degrees in),
        # up to one height sample (0.1 m) of interpolation and 1 cm of drop down the slope
        assert np.abs(offsets).max() <= 0.6 - RADIUS * np.sin(np.radians(72)) + 0.1 + 0.01 / 0.3


def test_ranges_and_errors():
    near = {"goal": FlatPatchSamplingCfg(num_patches=4, patch_radius=0.2, max_height_diff=0.05,
                                         x_range=(-0.5, 0.5), y_range=(0.0, 1.0))}  # fmt: skip
    terrain = TerrainGenerator(patchy_terrain(sub_terrains={"flat": MeshPlaneTerrainCfg(flat_patch_sampling=near)}))
    offsets = terrain.flat_patches["goal"].numpy() - terrain.terrain_origins[:, :, None, :]
    assert (np.abs(offsets[..., 0]) <= 0.5).all() and (offsets[..., 1] >= 0).all() and (offsets[..., 1] <= 1).all()

    too_high = {"x": FlatPatchSamplingCfg(num_patches=1, patch_radius=0.2, max_height_diff=0.05, z_range=(1.0, 2.0))}
    with pytest.raises(ValueError, match=r"sub_terrains\['flat'\].*found 0 of 1 flat patches"):
        TerrainGenerator(patchy_terrain(sub_terrains={"flat": MeshPlaneTerrainCfg(flat_patch_sampling=too_high)}))
    too_wide = {"x": FlatPatchSamplingCfg(num_patches=1, patch_radius=2.0, max_height_diff=0.05)}
    with pytest.raises(ValueError, match="no room for a flat patch of radius 2.0"):
        TerrainGenerator(patchy_terrain(sub_terrains={"flat": MeshPlaneTerrainCfg(flat_patch_sampling=too_wide)}))
    unset = {"x": FlatPatchSamplingCfg(num_patches=1, patch_radius=0.2)}
    with pytest.raises(ValueError, match="max_height_diff"):
        TerrainGenerator(patchy_terrain(sub_terrains={"flat": MeshPlaneTerrainCfg(flat_patch_sampling=unset)}))


@pytest.mark.parametrize("box_tiles_as", ["height_field", "boxes"])
def test_terrain_mesh_is_the_models_surface(box_tiles_as):
    terrain = TerrainGenerator(patchy_terrain(box_tiles_as))
    mesh = terrain.terrain_mesh
    extent = mesh.bounds[1] - mesh.bounds[0]
    assert extent[:2] == pytest.approx([2 * TILE + 2 * 1.0, 4 * TILE + 2 * 1.0])
    model, data = compiled_ground(terrain)
    # the mesh's highest point over random spots is where the model's ray lands
    rng = np.random.default_rng(0)
    for x, y in rng.uniform(mesh.bounds[0][:2] + 0.05, mesh.bounds[1][:2] - 0.05, size=(40, 2)):
        assert mesh_height_at(mesh, x, y) == pytest.approx(ground_height(model, data, x, y), abs=0.03)


def mesh_height_at(mesh, x: float, y: float) -> float:
    """Highest point of ``mesh``'s triangles over (x, y), by barycentric coordinates in the xy plane."""
    a, b, c = (mesh.vertices[mesh.faces][:, k] for k in range(3))
    det = (b[:, 1] - c[:, 1]) * (a[:, 0] - c[:, 0]) + (c[:, 0] - b[:, 0]) * (a[:, 1] - c[:, 1])
    upright = np.abs(det) > 1e-12  # vertical faces have no area in the xy plane
    det = np.where(upright, det, 1.0)
    w1 = ((b[:, 1] - c[:, 1]) * (x - c[:, 0]) + (c[:, 0] - b[:, 0]) * (y - c[:, 1])) / det
    w2 = ((c[:, 1] - a[:, 1]) * (x - c[:, 0]) + (a[:, 0] - c[:, 0]) * (y - c[:, 1])) / det
    w3 = 1 - w1 - w2
    over = upright & (w1 >= -1e-9) & (w2 >= -1e-9) & (w3 >= -1e-9)
    return float((w1 * a[:, 2] + w2 * b[:, 2] + w3 * c[:, 2])[over].max())


def test_disk_cache_reads_back_the_same_tiles(tmp_path, monkeypatch):
    cfg = patchy_terrain(use_cache=True, cache_dir=str(tmp_path))
    first = TerrainGenerator(cfg)
    files = sorted(p.name for p in tmp_path.iterdir())
    assert len(files) == 1 and files[0].endswith(".npz")
    # a second generator must read the file, not generate: make generating fail
    monkeypatch.setattr(TerrainGenerator, "_generate_tiles", lambda self: pytest.fail("generated again"))
    second = TerrainGenerator(cfg)
    assert sorted(p.name for p in tmp_path.iterdir()) == files
    np.testing.assert_array_equal(first.terrain_origins, second.terrain_origins)
    np.testing.assert_array_equal(first.terrain_mesh.vertices, second.terrain_mesh.vertices)
    assert torch.equal(first.flat_patches["spawn"], second.flat_patches["spawn"])
    # another seed is another terrain, in another file
    monkeypatch.undo()
    TerrainGenerator(cfg.replace(seed=6))
    assert len(list(tmp_path.iterdir())) == 2
