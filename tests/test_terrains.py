"""Terrains: generated tiles compile into the model as designed, seeded, with envs placed on them."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
import torch
from conftest import DEVICES, rendering_available

import simlab.sim as sim_utils
from simlab.assets import AssetBaseCfg, RigidObjectCfg
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.terrains import (
    ROUGH_TERRAINS_CFG,
    HfInvertedPyramidSlopedTerrainCfg,
    HfPyramidSlopedTerrainCfg,
    HfRandomUniformTerrainCfg,
    MeshInvertedPyramidStairsTerrainCfg,
    MeshPlaneTerrainCfg,
    MeshPyramidStairsTerrainCfg,
    MeshRandomGridTerrainCfg,
    TerrainGenerator,
    TerrainGeneratorCfg,
    TerrainImporterCfg,
    generate_terrain,
)
from simlab.utils import configclass

TILE = 3.0
SLOPE = dict(slope_range=(0.1, 0.3), platform_width=1.0, border_width=0.2)
STAIRS = dict(step_height_range=(0.05, 0.15), step_width=0.3, platform_width=1.0, border_width=0.2)


def small_terrain(seed: int | None = 3, **kw) -> TerrainGeneratorCfg:
    """Every sub-terrain kind in its own column, two difficulty levels."""
    cfg = TerrainGeneratorCfg(
        seed=seed,
        curriculum=True,
        size=(TILE, TILE),
        border_width=1.0,
        num_rows=2,
        num_cols=7,
        horizontal_scale=0.1,
        vertical_scale=0.005,
        sub_terrains={
            "flat": MeshPlaneTerrainCfg(),
            "rough": HfRandomUniformTerrainCfg(noise_range=(0.0, 0.06), noise_step=0.02, border_width=0.2),
            "slope": HfPyramidSlopedTerrainCfg(**SLOPE),
            "slope_inv": HfInvertedPyramidSlopedTerrainCfg(**SLOPE),
            "stairs": MeshPyramidStairsTerrainCfg(**STAIRS),
            "stairs_inv": MeshInvertedPyramidStairsTerrainCfg(**STAIRS),
            "boxes": MeshRandomGridTerrainCfg(grid_width=0.5, grid_height_range=(0.05, 0.1), platform_width=1.0),
        },
    )
    return cfg.replace(**kw)


def compiled(cfg: TerrainGeneratorCfg, num_envs: int = 4, device: str = "cpu"):
    @configclass
    class SceneCfg(InteractiveSceneCfg):
        terrain = TerrainImporterCfg(prim_path="/World/ground", terrain_type="generator", terrain_generator=cfg)
        light = AssetBaseCfg(prim_path="/World/light", spawn=sim_utils.DistantLightCfg(intensity=3000.0))

    scene_cfg = SceneCfg(num_envs=num_envs, env_spacing=2.0)
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device=device))
    scene = InteractiveScene(scene_cfg)
    sim.reset()
    return sim, scene


def ground_height(model: mujoco.MjModel, x: float, y: float) -> float:
    """Height of the model's static geometry under (x, y), by a ray cast down from 10 m."""
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    geomid = np.zeros(1, dtype=np.int32)
    distance = mujoco.mj_ray(model, data, np.array([x, y, 10.0]), np.array([0.0, 0.0, -1.0]), None, 1, -1, geomid)
    assert distance >= 0, f"no ground under ({x}, {y})"
    return 10.0 - distance


def design_centre_height(kind: str, difficulty: float) -> float:
    """The height at a tile's centre that each sub-terrain's definition gives."""
    lerp = lambda r: r[0] + difficulty * (r[1] - r[0])  # noqa: E731
    if kind == "flat":
        return 0.0
    if kind in ("slope", "slope_inv"):
        interior = TILE - 2 * SLOPE["border_width"]
        rise = lerp(SLOPE["slope_range"]) * (interior / 2 - SLOPE["platform_width"] / 2)
        return round(rise / 0.005) * 0.005 * (-1 if kind == "slope_inv" else 1)
    if kind in ("stairs", "stairs_inv"):
        room = TILE - 2 * STAIRS["border_width"] - STAIRS["platform_width"]
        steps = int(room // (2 * STAIRS["step_width"])) + 1
        return (steps + 1) * lerp(STAIRS["step_height_range"]) * (-1 if kind == "stairs_inv" else 1)
    if kind == "boxes":
        return lerp((0.05, 0.1))
    raise KeyError(kind)


@pytest.mark.parametrize("box_tiles_as", ["height_field", "boxes"])
def test_generated_terrain_compiles_with_the_designed_heights(box_tiles_as):
    terrain = TerrainGenerator(small_terrain(box_tiles_as=box_tiles_as))
    sim, scene = compiled(small_terrain(box_tiles_as=box_tiles_as))
    model = sim.model
    # rough, slope, slope_inv in two rows; stairs, inverted stairs and box grids too unless built as boxes
    assert model.nhfield == 2 * (6 if box_tiles_as == "height_field" else 3)
    kinds = {t.kind for t in terrain.tiles}
    assert kinds == set(small_terrain().sub_terrains)
    for tile in terrain.tiles:
        x, y = tile.corner + TILE / 2
        measured = ground_height(model, x, y)
        if tile.kind == "rough":
            assert 0.0 <= measured <= 0.06 + 1e-6
            # the height field's samples are the generated heights: transposition and scaling right
            heights = tile.geometry.heights
            for i, j in [(5, 9), (17, 4), (11, 20)]:
                sample = ground_height(model, tile.corner[0] + i * 0.1, tile.corner[1] + j * 0.1)
                assert sample == pytest.approx(heights[i, j], abs=1e-4)
            continue
        expected = design_centre_height(tile.kind, tile.difficulty)
        assert measured == pytest.approx(expected, abs=1e-4), tile.kind
        origin_z = terrain.terrain_origins[tile.row, tile.col, 2]
        if tile.kind == "slope_inv":  # an env starts on the highest point of the central 2 m patch
            assert expected < origin_z <= 0.0
        else:
            assert origin_z == pytest.approx(expected, abs=1e-4), tile.kind
    # difficulty grows with the row (curriculum), and the border surrounds the grid at ground level
    for col in range(7):
        assert terrain.tiles[col * 2].difficulty < terrain.tiles[col * 2 + 1].difficulty
    assert ground_height(model, -TILE - 0.5, 0.0) == pytest.approx(0.0, abs=1e-6)


def test_same_seed_same_terrain_and_cache():
    first, second = TerrainGenerator(small_terrain(seed=7)), TerrainGenerator(small_terrain(seed=7))
    other = TerrainGenerator(small_terrain(seed=8))
    rough = [t for t in first.tiles if t.kind == "rough"]
    assert all(
        np.array_equal(a.geometry.heights, b.geometry.heights)
        for a, b in zip(rough, [t for t in second.tiles if t.kind == "rough"], strict=True)
    )
    assert np.array_equal(first.terrain_origins, second.terrain_origins)
    assert not all(
        np.array_equal(a.geometry.heights, b.geometry.heights)
        for a, b in zip(rough, [t for t in other.tiles if t.kind == "rough"], strict=True)
    )
    assert generate_terrain(small_terrain(seed=7)) is generate_terrain(small_terrain(seed=7))
    # and the compiled models carry the same height field data
    data = []
    for _ in range(2):
        sim, _ = compiled(small_terrain(seed=7))
        data.append(sim.model.hfield_data.copy())
        sim_utils.SimulationContext.clear_instance()
    assert np.array_equal(*data)


@pytest.mark.parametrize("device", DEVICES)
def test_env_origins_on_tiles_with_levels(device):
    cfg = small_terrain().replace(num_rows=4, num_cols=2)
    cfg.sub_terrains = {"stairs": MeshPyramidStairsTerrainCfg(**STAIRS), "flat": MeshPlaneTerrainCfg()}

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        terrain = TerrainImporterCfg(prim_path="/World/ground", terrain_generator=cfg, max_init_terrain_level=1)
        ball = RigidObjectCfg(
            prim_path="{ENV_REGEX_NS}/Ball",
            spawn=sim_utils.SphereCfg(radius=0.1, rigid_props=sim_utils.RigidBodyPropertiesCfg()),
        )

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device=device))
    scene = InteractiveScene(SceneCfg(num_envs=8, env_spacing=2.0))
    sim.reset()
    terrain = scene.terrain
    assert scene["terrain"] is terrain
    origins = terrain.terrain_origins
    levels, types = terrain.terrain_levels, terrain.terrain_types
    assert int(levels.max()) <= 1 and types.tolist() == [0, 0, 0, 0, 1, 1, 1, 1]
    assert torch.equal(scene.env_origins, origins[levels, types])
    # each ball dropped 0.3 m above its env origin comes to rest on its own tile
    ball_obj = scene["ball"]
    state = ball_obj.data.default_root_state.clone()
    state[:, :3] = scene.env_origins + torch.tensor([0.0, 0.0, 0.4], device=device)
    ball_obj.write_root_state_to_sim(state)
    for _ in range(200):
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())
    rest = ball_obj.data.root_pos_w
    torch.testing.assert_close(rest[:, :2], scene.env_origins[:, :2], atol=0.05, rtol=0)
    torch.testing.assert_close(rest[:, 2], scene.env_origins[:, 2] + 0.1, atol=0.01, rtol=0)

    # the curriculum: by mask (move_up/down for every env) and by ids
    before = levels.clone()
    mask = torch.tensor([True, True, False, False, True, False, False, False], device=device)
    up = torch.ones(8, dtype=torch.bool, device=device)
    terrain.update_env_origins(mask, up, ~up)
    assert torch.equal(levels, torch.where(mask, before + 1, before))
    # ids in any order, with move_up/down in that order: env 3 moves down, env 2 stays
    terrain.update_env_origins([3, 2], torch.tensor([False, False]), torch.tensor([True, False]))
    assert levels[2:4].tolist() == [int(before[2]), max(int(before[3]) - 1, 0)]
    assert torch.equal(scene.env_origins, origins[levels, types])
    # past the hardest row, an env goes to a random row
    for _ in range(4):
        terrain.update_env_origins(None, up, ~up)
    assert bool(((levels >= 0) & (levels < 4)).all())


def test_plane_terrain_keeps_the_env_grid():
    @configclass
    class SceneCfg(InteractiveSceneCfg):
        terrain = TerrainImporterCfg(prim_path="/World/ground", terrain_type="plane")

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device="cpu"))
    scene = InteractiveScene(SceneCfg(num_envs=4, env_spacing=3.0))
    sim.reset()
    assert sim.model.ngeom == 1 and scene.terrain.terrain_origins is None
    assert torch.equal(scene.env_origins, sim.env_origins)
    assert float(torch.cdist(scene.env_origins, scene.env_origins).max()) == pytest.approx(3.0 * 2**0.5)


def test_bad_terrain_configs_name_the_setting():
    with pytest.raises(ValueError, match="terrain_type='usd'"):
        usd = TerrainImporterCfg(prim_path="/g", terrain_type="usd")
        usd.class_type(usd)
    too_wide = small_terrain(sub_terrains={"s": MeshPyramidStairsTerrainCfg(platform_width=5.0)})
    with pytest.raises(ValueError, match=r"sub_terrains\['s'\].*platform_width=5.0"):
        TerrainGenerator(too_wide)
    with pytest.raises(ValueError, match="proportions sum to 0"):
        TerrainGenerator(small_terrain(sub_terrains={"f": MeshPlaneTerrainCfg(proportion=0.0)}))
    with pytest.raises(ValueError, match="border_width"):
        TerrainGenerator(small_terrain(sub_terrains={"r": HfRandomUniformTerrainCfg(border_width=2.0)}))
    # a sampling so fine that the terrain would not fit in memory is refused before generating it
    with pytest.raises(ValueError, match=r"cannot fit: 10 x 20 tiles .* every 0.001 m .* raise horizontal_scale"):
        TerrainGenerator(ROUGH_TERRAINS_CFG.replace(horizontal_scale=0.001))


def test_rough_preset_is_isaac_labs_grid():
    assert (ROUGH_TERRAINS_CFG.num_rows, ROUGH_TERRAINS_CFG.num_cols, ROUGH_TERRAINS_CFG.size) == (10, 20, (8.0, 8.0))
    assert sum(s.proportion for s in ROUGH_TERRAINS_CFG.sub_terrains.values()) == pytest.approx(1.0)
    # Isaac Lab's sub-terrains and proportions; with the curriculum, columns go to the kinds by
    # proportion: 4 of pyramid stairs, 4 of inverted stairs, 4 of boxes, 4 of roughness, 2 + 2 of slopes
    subs = ROUGH_TERRAINS_CFG.sub_terrains
    assert {name: (type(sub).__name__, sub.proportion) for name, sub in subs.items()} == {
        "pyramid_stairs": ("MeshPyramidStairsTerrainCfg", 0.2),
        "pyramid_stairs_inv": ("MeshInvertedPyramidStairsTerrainCfg", 0.2),
        "boxes": ("MeshRandomGridTerrainCfg", 0.2),
        "random_rough": ("HfRandomUniformTerrainCfg", 0.2),
        "hf_pyramid_slope": ("HfPyramidSlopedTerrainCfg", 0.1),
        "hf_pyramid_slope_inv": ("HfInvertedPyramidSlopedTerrainCfg", 0.1),
    }
    for name in ("pyramid_stairs", "pyramid_stairs_inv"):
        stairs = subs[name]
        assert (stairs.step_height_range, stairs.step_width, stairs.platform_width, stairs.border_width) == (
            (0.05, 0.23),
            0.3,
            3.0,
            1.0,
        )
    terrain = TerrainGenerator(ROUGH_TERRAINS_CFG.replace(seed=1, curriculum=True))
    kinds = {t.col: t.kind for t in terrain.tiles}
    assert [kinds[c] for c in range(20)] == ["pyramid_stairs"] * 4 + ["pyramid_stairs_inv"] * 4 + ["boxes"] * 4 + [
        "random_rough"
    ] * 4 + ["hf_pyramid_slope"] * 2 + ["hf_pyramid_slope_inv"] * 2
    # rows are difficulty levels: the stairs' steps rise with the row (0.05 m at row 0 .. 0.23 m at row 9)
    step = {t.row: t.geometry.origin[2] / 7 for t in terrain.tiles if t.col == 0}  # the platform: 7 steps up
    assert step[0] < 0.07 and step[9] > 0.21 and all(step[r] < step[r + 1] for r in range(9))


@pytest.mark.skipif(not rendering_available(), reason="no offscreen GL backend")
def test_rough_terrain_renders(tmp_path):
    import imageio.v3 as iio

    from simlab.sim.renderer import OffscreenRenderer

    cfg = ROUGH_TERRAINS_CFG.replace(
        seed=0, curriculum=True, num_rows=3, num_cols=6, border_width=2.0, size=(4.0, 4.0), color_scheme="height"
    )
    for sub in cfg.sub_terrains.values():  # shrink Isaac Lab's 8 m tiles' features to 4 m tiles
        if hasattr(sub, "platform_width"):
            sub.platform_width = 1.0
        if hasattr(sub, "border_width"):
            sub.border_width = min(sub.border_width, 0.25)
    sim, scene = compiled(cfg, num_envs=2)
    renderer = OffscreenRenderer(sim.model, 480, 320, max_envs=2)
    image = renderer.render(sim.physics, [0, 1], np.zeros((2, 3)), eye=(-14.0, -12.0, 12.0), lookat=(0.0, 0.0, 0.0))
    renderer.close()
    iio.imwrite(tmp_path / "rough_terrain.png", image)
    assert image.shape == (320, 480, 3)
    # terrain fills the view: many distinct shades, no empty background band in the middle
    assert len(np.unique(image.reshape(-1, 3), axis=0)) > 500
    assert image[120:200].std() > 10


class VelocityCommands:
    """The one piece of a command manager that terrain_levels_vel reads."""

    def __init__(self, commands: torch.Tensor):
        self.commands = commands

    def get_command(self, name: str) -> torch.Tensor:
        assert name == "base_velocity"
        return self.commands


def test_terrain_levels_vel_moves_envs_between_rows():
    from types import SimpleNamespace

    from simlab.envs.mdp import terrain_levels_vel

    cfg = small_terrain().replace(num_rows=4, num_cols=1)
    cfg.sub_terrains = {"flat": MeshPlaneTerrainCfg()}

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        terrain = TerrainImporterCfg(prim_path="/World/ground", terrain_generator=cfg, max_init_terrain_level=0)
        robot = RigidObjectCfg(
            prim_path="{ENV_REGEX_NS}/Robot",
            spawn=sim_utils.SphereCfg(radius=0.1, rigid_props=sim_utils.RigidBodyPropertiesCfg()),
        )

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device="cpu"))
    scene = InteractiveScene(SceneCfg(num_envs=4, env_spacing=2.0))
    sim.reset()
    terrain = scene.terrain
    terrain.terrain_levels[:] = torch.tensor([1, 1, 1, 1])
    terrain.update_env_origins(None, torch.zeros(4, dtype=torch.bool), torch.zeros(4, dtype=torch.bool))
    # env 0 walked 2 m (> half a 3 m tile); env 1 stayed although told to walk 1 m/s; env 2 walked
    # 1 m as told to walk 0.1 m/s; env 3 walked out too but did not finish its episode
    walked = torch.tensor([[2.0, 0.0], [0.0, 0.0], [0.0, 1.0], [2.0, 0.0]])
    pose = scene["robot"].data.default_root_state[:, :7].clone()
    pose[:, :3] = scene.env_origins + torch.cat([walked, torch.full((4, 1), 0.1)], dim=1)
    scene["robot"].write_root_pose_to_sim(pose)
    commands = torch.tensor([[1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.0, 0.0]])
    env = SimpleNamespace(
        scene=scene, command_manager=VelocityCommands(commands), max_episode_length_s=10.0, num_envs=4, device="cpu"
    )
    finished = torch.tensor([True, True, True, False])
    mean_level = terrain_levels_vel(env, finished)
    assert terrain.terrain_levels.tolist() == [2, 0, 1, 1]
    assert float(mean_level) == pytest.approx(1.0)
    assert torch.equal(scene.env_origins, terrain.terrain_origins[terrain.terrain_levels, 0])


def test_isaac_lab_velocity_scene_terrain_config():
    """The terrain field of Isaac Lab's LocomotionVelocityRoughEnvCfg scene, as written there."""
    from simlab.terrains.config.rough import ROUGH_TERRAINS_CFG as PRESET
    from simlab.utils.assets import ISAACLAB_NUCLEUS_DIR

    @configclass
    class MySceneCfg(InteractiveSceneCfg):
        terrain = TerrainImporterCfg(
            prim_path="/World/ground",
            terrain_type="generator",
            terrain_generator=PRESET.replace(seed=5),
            max_init_terrain_level=5,
            collision_group=-1,
            physics_material=sim_utils.RigidBodyMaterialCfg(
                friction_combine_mode="multiply",
                restitution_combine_mode="multiply",
                static_friction=1.0,
                dynamic_friction=1.0,
            ),
            visual_material=sim_utils.MdlFileCfg(
                mdl_path=f"{ISAACLAB_NUCLEUS_DIR}/Materials/TilesMarbleSpiderWhiteBrickBondHoned.mdl",
                project_uvw=True,
                texture_scale=(0.25, 0.25),
            ),
            debug_vis=False,
        )

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device="cpu"))
    scene = InteractiveScene(MySceneCfg(num_envs=40, env_spacing=2.5))
    sim.reset()
    terrain = scene.terrain
    assert terrain.terrain_origins.shape == (10, 20, 3)
    assert int(terrain.terrain_levels.max()) <= 5
    assert sorted(set(terrain.terrain_types.tolist())) == list(range(20))  # two envs per column
    assert sim.model.nhfield > 0 and np.allclose(sim.model.geom_friction[:, 0], 1.0)
    # the 20 m border around the 80 m x 160 m grid is flat ground
    assert ground_height(sim.model, 0.0, 80.0 + 10.0) == pytest.approx(0.0, abs=1e-6)


def test_without_a_seed_of_its_own_the_global_numpy_seed_fixes_the_terrain():
    from simlab.utils.seed import configure_seed

    def heights(global_seed: int) -> list[np.ndarray]:
        configure_seed(global_seed)  # what seeding the env does
        generator = TerrainGenerator(small_terrain(seed=None))
        return [t.geometry.heights for t in generator.tiles if t.kind == "rough"]

    first, again, other = heights(11), heights(11), heights(12)
    assert all(np.array_equal(a, b) for a, b in zip(first, again, strict=True))
    assert not all(np.array_equal(a, b) for a, b in zip(first, other, strict=True))


def test_reset_root_state_from_terrain_puts_the_asset_on_its_tiles_flat_patches():
    from types import SimpleNamespace

    from simlab.envs import mdp
    from simlab.managers import SceneEntityCfg
    from simlab.terrains import FlatPatchSamplingCfg

    spots = {"init_pos": FlatPatchSamplingCfg(num_patches=5, patch_radius=0.2, max_height_diff=0.01)}
    cfg = small_terrain().replace(num_rows=2, num_cols=2)
    cfg.sub_terrains = {
        "stairs": MeshPyramidStairsTerrainCfg(**STAIRS, flat_patch_sampling=spots),
        "slope": HfPyramidSlopedTerrainCfg(**SLOPE, flat_patch_sampling=spots),
    }

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        terrain = TerrainImporterCfg(prim_path="/World/ground", terrain_generator=cfg)
        robot = RigidObjectCfg(
            prim_path="{ENV_REGEX_NS}/Ball",
            spawn=sim_utils.SphereCfg(radius=0.1, rigid_props=sim_utils.RigidBodyPropertiesCfg()),
            init_state=RigidObjectCfg.InitialStateCfg(pos=(0.0, 0.0, 0.1)),
        )

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device="cpu"))
    scene = InteractiveScene(SceneCfg(num_envs=6, env_spacing=2.0))
    sim.reset()
    env = SimpleNamespace(scene=scene, device="cpu", num_envs=6)
    robot, terrain = SceneEntityCfg("robot"), scene.terrain
    mask = torch.tensor([True, True, True, True, False, True])
    before = scene["robot"].data.root_pos_w[4].clone()
    mdp.reset_root_state_from_terrain(env, mask, {"yaw": (1.0, 1.0)}, {}, asset_cfg=robot)
    pos = scene["robot"].data.root_pos_w
    patches = terrain.flat_patches["init_pos"][terrain.terrain_levels, terrain.terrain_types]  # (envs, 5, 3)
    for env_id in mask.nonzero().flatten().tolist():  # on one of its own tile's patches, 0.1 m up
        distance = (patches[env_id] + torch.tensor([0.0, 0.0, 0.1]) - pos[env_id]).norm(dim=-1)
        assert distance.min() < 1e-5, (env_id, pos[env_id], patches[env_id])
    torch.testing.assert_close(pos[4], before)  # not reset
    yaw = scene["robot"].data.heading_w[mask]
    torch.testing.assert_close(yaw, torch.ones_like(yaw))
    with pytest.raises(ValueError, match=r"\['x'\] are not used .*allowed: \['roll', 'pitch', 'yaw'\]"):
        mdp.reset_root_state_from_terrain(env, mask, {"x": (0.0, 1.0)}, {}, asset_cfg=robot)
    sim_utils.SimulationContext.clear_instance()
