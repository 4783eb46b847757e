"""Isaac Lab's Nucleus asset paths: a ``UsdFileCfg`` naming a robot or prop simlab ships spawns simlab's
model of it (``simlab.sim.spawners.from_files.usd_stand_ins``); any other USD path is one line of error."""

from __future__ import annotations

import importlib
import os
import pkgutil
from pathlib import Path

import mujoco
import pytest
import torch

import simlab.robots
import simlab.sim as sim_utils
from simlab.assets import ArticulationCfg, AssetBaseCfg, RigidObjectCfg
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.sim.spawners.from_files.usd_stand_ins import USD_STAND_INS, nucleus_key
from simlab.utils import configclass
from simlab.utils.assets import ISAAC_NUCLEUS_DIR, ISAACLAB_NUCLEUS_DIR
from simlab.utils.errors import ConfigError

ROBOT_CFGS = {
    os.path.basename(cfg.spawn.asset_path): cfg
    for module in pkgutil.iter_modules(simlab.robots.__path__)
    for cfg in vars(importlib.import_module(f"simlab.robots.{module.name}")).values()
    if isinstance(cfg, ArticulationCfg) and isinstance(cfg.spawn, sim_utils.MjcfFileCfg)
}
"""simlab's robot configs (of every module of simlab.robots) by the MJCF file they spawn."""


def _scene(**entities) -> InteractiveScene:
    namespace = {"__annotations__": dict.fromkeys(entities, object), **entities}
    cfg = configclass(type("SceneCfg", (InteractiveSceneCfg,), namespace))(num_envs=2, env_spacing=3.0)
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device="cpu"))
    scene = InteractiveScene(cfg)
    sim.reset()
    return scene


def test_nucleus_key_finds_the_asset_whatever_the_server():
    suffix = "IsaacLab/Robots/Unitree/Go2/go2.usd"
    for root in (
        ISAAC_NUCLEUS_DIR,
        "omniverse://localhost/NVIDIA/Assets/Isaac/4.5/Isaac",
        "https://omniverse-content-production.s3-us-west-2.amazonaws.com/Assets/Isaac/5.1/Isaac",
        "/home/me/isaac_assets/Isaac",
    ):
        assert nucleus_key(f"{root}/{suffix}") == suffix
    assert f"{ISAACLAB_NUCLEUS_DIR}/Robots/Unitree/Go2/go2.usd" == f"{ISAAC_NUCLEUS_DIR}/{suffix}"


@pytest.mark.parametrize("key", sorted(USD_STAND_INS))
def test_every_table_entry_builds_a_scene(key):
    """Robots spawn as simlab's robot config of the same MJCF (same joints); props as what the table says."""
    path = f"{ISAAC_NUCLEUS_DIR}/{key}"
    row = USD_STAND_INS[key]
    if row.model.endswith(".xml"):
        assert row.model in ROBOT_CFGS, f"{row.model} has no robot config in simlab.robots"
        shipped = ROBOT_CFGS[row.model]
        ported = shipped.replace(prim_path="{ENV_REGEX_NS}/Robot", spawn=sim_utils.UsdFileCfg(usd_path=path))
        robot = _scene(robot=ported)["robot"]
        reference = _scene(robot=shipped.replace(prim_path="{ENV_REGEX_NS}/Robot"))["robot"]
        assert robot.joint_names == reference.joint_names and robot.body_names == reference.body_names
        assert robot.num_instances == 2
    elif "DexCube" in key:
        spawn = sim_utils.UsdFileCfg(usd_path=path, rigid_props=sim_utils.RigidBodyPropertiesCfg())
        cube = _scene(cube=RigidObjectCfg(prim_path="{ENV_REGEX_NS}/Cube", spawn=spawn))["cube"]
        assert cube.num_instances == 2
    else:  # a static prop: the table, the ground
        _scene(prop=AssetBaseCfg(prim_path="/World/Prop", spawn=sim_utils.UsdFileCfg(usd_path=path)))
        model = sim_utils.SimulationContext.instance().model
        geom = model.geom(0)
        assert model.ngeom == 1 and geom.name == "Prop" or geom.name.startswith("Prop/")


def test_robot_cfg_naming_a_shipped_robots_usd_keeps_its_settings():
    """Isaac Lab's Go2 config (its USD path and rigid/articulation settings) builds and stands the robot."""
    spawn = sim_utils.UsdFileCfg(
        usd_path=f"{ISAACLAB_NUCLEUS_DIR}/Robots/Unitree/Go2/go2.usd",
        activate_contact_sensors=True,
        rigid_props=sim_utils.RigidBodyPropertiesCfg(disable_gravity=True, max_depenetration_velocity=1.0),
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(
            enabled_self_collisions=False, solver_position_iteration_count=4, solver_velocity_iteration_count=0
        ),
    )
    cfg = ROBOT_CFGS["unitree_go2.xml"].replace(prim_path="{ENV_REGEX_NS}/Robot", spawn=spawn)
    scene = _scene(robot=cfg)
    robot = scene["robot"]
    assert robot.num_joints == 12
    # disable_gravity carried over: the floating robot does not fall
    z0 = robot.data.root_pos_w[:, 2].clone()
    for _ in range(50):
        scene.write_data_to_sim()
        sim_utils.SimulationContext.instance().step()
        scene.update(0.005)
    assert torch.allclose(robot.data.root_pos_w[:, 2], z0, atol=0.02)


def test_isaaclab_lift_config_with_the_dex_cube_usd_runs():
    """Isaac Lab's lift (Franka) names its robot and cube by Nucleus USD paths; the env builds and steps."""
    from simlab.envs import ManagerBasedRLEnv
    from simlab.robots.franka import FRANKA_PANDA_CFG
    from simlab.tasks.manager_based.manipulation.lift.config.franka.joint_pos_env_cfg import FrankaCubeLiftEnvCfg

    env_cfg = FrankaCubeLiftEnvCfg()
    env_cfg.scene.num_envs = 2
    env_cfg.sim.device = "cpu"
    env_cfg.scene.robot = FRANKA_PANDA_CFG.replace(
        prim_path="{ENV_REGEX_NS}/Robot",
        spawn=sim_utils.UsdFileCfg(
            usd_path=f"{ISAACLAB_NUCLEUS_DIR}/Robots/FrankaEmika/panda_instanceable.usd",
            activate_contact_sensors=False,
            rigid_props=sim_utils.RigidBodyPropertiesCfg(disable_gravity=False, max_depenetration_velocity=5.0),
            articulation_props=sim_utils.ArticulationRootPropertiesCfg(
                enabled_self_collisions=True, solver_position_iteration_count=8, solver_velocity_iteration_count=0
            ),
        ),
    )
    # Isaac Lab's object, as its joint_pos_env_cfg.py writes it
    env_cfg.scene.object = RigidObjectCfg(
        prim_path="{ENV_REGEX_NS}/Object",
        init_state=RigidObjectCfg.InitialStateCfg(pos=[0.5, 0, 0.055], rot=[1, 0, 0, 0]),
        spawn=sim_utils.UsdFileCfg(
            usd_path=f"{ISAAC_NUCLEUS_DIR}/Props/Blocks/DexCube/dex_cube_instanceable.usd",
            scale=(0.8, 0.8, 0.8),
            rigid_props=sim_utils.RigidBodyPropertiesCfg(
                solver_position_iteration_count=16,
                solver_velocity_iteration_count=1,
                max_angular_velocity=1000.0,
                max_linear_velocity=1000.0,
                max_depenetration_velocity=5.0,
                disable_gravity=False,
            ),
        ),
    )
    env = ManagerBasedRLEnv(env_cfg)
    try:
        env.reset()
        for _ in range(10):
            env.step(torch.zeros(env.num_envs, env.action_manager.total_action_dim))
        cube = env.scene["object"]
        # the 4.8 cm cube rests on the table (top at z = 0): its centre 2.4 cm above it
        assert torch.allclose(cube.data.root_pos_w[:, 2], torch.full((2,), 0.024), atol=0.005)
    finally:
        env.close()


def test_an_unknown_usd_path_is_one_line_listing_what_is_available():
    spawn = sim_utils.UsdFileCfg(usd_path=f"{ISAAC_NUCLEUS_DIR}/Robots/Kinova/Gen3/gen3.usd")
    with pytest.raises(ConfigError) as err:
        _scene(robot=AssetBaseCfg(prim_path="/World/Robot", spawn=spawn))
    message = str(err.value)
    assert "\n" not in message
    assert "gen3.usd" in message and "MjcfFileCfg" in message and "go2.usd" in message
    assert "dex_cube_instanceable.usd" in message and "Near it" not in message  # nothing near a Kinova
    spawn = sim_utils.UsdFileCfg(usd_path=f"{ISAACLAB_NUCLEUS_DIR}/Robots/Unitree/G1/g1_29dof.usd")
    with pytest.raises(ConfigError) as err:
        _scene(robot=AssetBaseCfg(prim_path="/World/Robot", spawn=spawn))
    near = (
        "Near it, below ISAAC_NUCLEUS_DIR: IsaacLab/Robots/Unitree/G1/g1.usd, IsaacLab/Robots/Unitree/G1/g1_minimal.usd"
    )
    assert str(err.value).endswith(f"{near}.")  # the files of its folder, whole paths
    spawn = sim_utils.UsdFileCfg(usd_path=f"{ISAAC_NUCLEUS_DIR}/Robots/Unitree/H1/h1.usd")
    with pytest.raises(ConfigError, match=r"Near it, below ISAAC_NUCLEUS_DIR: IsaacLab/Robots/Unitree/H1/h1\.usd\.$"):
        _scene(robot=AssetBaseCfg(prim_path="/World/Robot", spawn=spawn))  # the same file name elsewhere


def test_docs_list_every_entry():
    docs = (Path(__file__).resolve().parents[1] / "docs" / "porting.md").read_text()
    assert all(f"| `{key}` |" in docs for key in USD_STAND_INS)


def test_usd_variants_are_refused_on_a_stand_in():
    spawn = sim_utils.UsdFileCfg(
        usd_path=f"{ISAACLAB_NUCLEUS_DIR}/Robots/FrankaEmika/panda_instanceable.usd", variants={"Gripper": "None"}
    )
    with pytest.raises(ConfigError, match="variants"):
        _scene(robot=ROBOT_CFGS["franka_panda.xml"].replace(prim_path="{ENV_REGEX_NS}/Robot", spawn=spawn))


def test_rough_plane_stands_in_as_a_height_field_the_ray_caster_scans():
    """Isaac Sim's rough_plane.usd (the ray-caster tutorials' ground) spawns a static height field whose
    bumps (0 to 10 cm) the ray caster reads."""
    from simlab.sensors import RayCasterCfg, patterns

    ground = AssetBaseCfg(
        prim_path="/World/ground",
        spawn=sim_utils.UsdFileCfg(usd_path=f"{ISAAC_NUCLEUS_DIR}/Environments/Terrains/rough_plane.usd"),
    )
    ball = RigidObjectCfg(
        prim_path="{ENV_REGEX_NS}/Ball",
        spawn=sim_utils.SphereCfg(radius=0.25, rigid_props=sim_utils.RigidBodyPropertiesCfg(kinematic_enabled=True)),
        init_state=RigidObjectCfg.InitialStateCfg(pos=(0.0, 0.0, 2.0)),
    )
    scanner = RayCasterCfg(
        prim_path="{ENV_REGEX_NS}/Ball",
        mesh_prim_paths=["/World/ground"],
        pattern_cfg=patterns.GridPatternCfg(resolution=0.1, size=(2.0, 2.0)),
        ray_alignment="yaw",
    )
    scene = _scene(ground=ground, ball=ball, scanner=scanner)
    model = sim_utils.SimulationContext.instance().model
    assert model.geom("ground").type == mujoco.mjtGeom.mjGEOM_HFIELD and model.geom("ground").bodyid == 0
    scene.update(0.005)
    heights = scene["scanner"].data.ray_hits_w[..., 2]
    assert torch.isfinite(heights).all() and heights.min() >= -1e-4 and heights.max() <= 0.1 + 1e-4
    assert heights.std() > 0.01  # bumps, not a plane


def test_the_robot_stand_holds_the_arm_at_its_top_and_reaches_the_ground():
    """Isaac Sim's robot stand, as Isaac Lab's diff-IK tutorial mounts its arm (scaled by 2, at the robot's
    base, the ground 1.05 m below): a static box whose top is at the prop's origin and whose foot is 1.03 m
    below it (where Isaac Lab's arms demo puts the ground)."""
    spawn = sim_utils.UsdFileCfg(
        usd_path=f"{ISAAC_NUCLEUS_DIR}/Props/Mounts/Stand/stand_instanceable.usd", scale=(2.0, 2.0, 2.0)
    )
    _scene(table=AssetBaseCfg(prim_path="{ENV_REGEX_NS}/Table", spawn=spawn))
    model = sim_utils.SimulationContext.instance().model
    assert model.ngeom == 1  # a static box (each env is a world of its own)
    geom = model.geom(0)
    assert geom.type == mujoco.mjtGeom.mjGEOM_BOX and model.body_dofnum[geom.bodyid] == 0
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    top, foot = data.geom_xpos[0, 2] + geom.size[2], data.geom_xpos[0, 2] - geom.size[2]
    assert abs(top) < 1e-9 and abs(foot + 1.03) < 1e-6


def test_the_other_anymal_paths_of_isaac_labs_configs_name_the_same_models():
    """Isaac Lab's ANYmal configs keep a second USD path beside their own (commented out in
    isaaclab_assets' anymal.py; Isaac Sim's older ANYmal-C file is what several of its tests spawn)."""
    assert USD_STAND_INS["Robots/ANYbotics/anymal_instanceable.usd"].model == "anybotics_anymal_c.xml"
    assert USD_STAND_INS["IsaacLab/Robots/ANYbotics/ANYmal-D/anymal_d_minimal.usd"].model == "anybotics_anymal_d.xml"
