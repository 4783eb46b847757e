"""Isaac Lab 3.0's cloner calls of a direct env's ``_setup_scene`` (simlab.v3.cloner, issue 42): the scene
has made every env already, so ``replicate`` checks that the plan asks for simlab's layout, and
``grid_transforms`` gives the scene's own grid; the ported 3.0 direct cartpole clones with them and steps."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
import torch

import simlab.sim as sim_utils
from simlab.utils.errors import ConfigError
from simlab.v3 import cloner
from simlab.v3 import scene as scene3

PORTED3 = Path(__file__).parent / "ported3"


def test_grid_transforms_is_the_scenes_grid():
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    scene = scene3.InteractiveScene(scene3.InteractiveSceneCfg(num_envs=7, env_spacing=2.5))
    sim.reset()
    positions, orientations = cloner.grid_transforms(7, 2.5)
    assert torch.equal(positions, scene.env_origins)
    assert torch.equal(orientations, torch.tensor([[0.0, 0.0, 0.0, 1.0]]).expand(7, 4))  # identity, (x, y, z, w)
    with pytest.raises(ConfigError, match="simlab's worlds are z-up"):
        cloner.grid_transforms(7, 2.5, up_axis="y")


def test_replicate_accepts_the_scenes_layout_and_refuses_another():
    sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    scene3.InteractiveScene(scene3.InteractiveSceneCfg(num_envs=4, env_spacing=2.0))
    positions = cloner.grid_transforms(4, 2.0)[0]
    cloner.replicate(cloner.clone_plan_from_env_0("/World/envs/env_0", "/World/envs/env_{}", 4, "cpu", positions))
    cloner.replicate(cloner.clone_plan_from_env_0("/World/envs/env_0", "/World/envs/env_{}", 4, positions))
    with pytest.raises(ConfigError, match="the plan makes 8 envs, the scene has 4"):
        cloner.replicate(cloner.clone_plan_from_env_0("/World/envs/env_0", "/World/envs/env_{}", 8, positions))
    with pytest.raises(ConfigError, match="simlab's scene makes its envs at '/World/envs/env_\\{\\}'"):
        cloner.replicate(cloner.clone_plan_from_env_0("/World/Origin1", "/World/Origin{}", 4, positions))
    with pytest.raises(ConfigError, match=r"positions must be \(4, 3\)"):
        cloner.replicate(cloner.clone_plan_from_env_0("/World/envs/env_0", "/World/envs/env_{}", 4, positions[:2]))


def _box_scene(**terrain):
    from simlab.assets import RigidObjectCfg

    box = RigidObjectCfg(
        prim_path="{ENV_REGEX_NS}/Box",
        spawn=sim_utils.CuboidCfg(size=(0.1, 0.1, 0.1), rigid_props=sim_utils.RigidBodyPropertiesCfg()),
        init_state=RigidObjectCfg.InitialStateCfg(pos=(0.0, 0.0, 1.0)),
    )
    cfg = scene3.InteractiveSceneCfg(num_envs=4, env_spacing=2.0)
    cfg.box = box
    if terrain:
        from simlab.terrains import TerrainImporterCfg

        cfg.terrain = TerrainImporterCfg(prim_path="/World/ground", **terrain)
    return scene3.InteractiveScene(cfg)


def test_replicate_places_the_envs_at_the_plans_positions():
    """As Isaac Lab 3.0 (its scene's env origins are the published plan's positions where no terrain places
    the envs): positions other than the scene's grid become the env origins, and the envs' bodies move with them."""
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    scene = _box_scene()
    positions = cloner.grid_transforms(4, 5.0)[0] + torch.tensor([0.0, 0.0, 0.5])
    assert not torch.equal(positions, scene.env_origins)  # the scene's grid is 2.0 apart
    cloner.replicate(cloner.clone_plan_from_env_0("/World/envs/env_0", "/World/envs/env_{}", 4, positions))
    sim.reset()
    scene.reset()
    assert torch.equal(scene.env_origins, positions) and torch.equal(sim.env_origins, positions)
    box = scene["box"]
    torch.testing.assert_close(box.data.root_pos_w, positions + torch.tensor([0.0, 0.0, 1.0]))


def test_a_terrain_keeps_its_origins_as_in_isaac_lab_3_0():
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    scene = _box_scene(terrain_type="plane", env_spacing=3.0)
    terrain_origins = scene.env_origins.clone()
    positions = cloner.grid_transforms(4, 5.0)[0]
    cloner.replicate(cloner.clone_plan_from_env_0("/World/envs/env_0", "/World/envs/env_{}", 4, positions))
    sim.reset()
    assert torch.equal(scene.env_origins, terrain_origins)


def test_the_3_0_direct_cartpole_clones_with_the_cloner_and_steps():
    sys.path.insert(0, str(PORTED3))
    try:
        from isaaclab3_cartpole.cartpole_direct_env import CartpoleEnv
        from isaaclab3_cartpole.cartpole_direct_env_cfg import CartpoleEnvCfg

        cfg = CartpoleEnvCfg()
        cfg.scene.num_envs, cfg.sim.device = 3, "cpu"
        env = CartpoleEnv(cfg)
        try:
            env.reset()
            for _ in range(3):
                obs, *_ = env.step(torch.ones(3, 1))
            assert obs["policy"].shape == (3, 4) and torch.isfinite(obs["policy"]).all()
        finally:
            env.close()
    finally:
        sys.path.remove(str(PORTED3))
        for name in [m for m in sys.modules if m.split(".")[0].startswith("isaaclab3_")]:
            del sys.modules[name]
