"""The humanoid robots: Unitree H1, G1 with hands (Isaac Lab's layout) and the 29-DoF G1 (mjlab's).

Each MJCF model compiles alone with the published joint names in MuJoCo's depth-first order and the
published total mass; each articulation exposes them level by level down the tree (Isaac Lab's
order) with its actuator groups' gains. Standing is checked two ways, because the configs' gains
cannot hold a humanoid up on their own (measured: under H1_CFG's or G1_CFG's gains with targets at
the default pose, the robot pitches over within 2 s; balancing is the policy's job, as in Isaac Lab):

* hung by its base (``fix_root_link``), each robot holds its default pose under its own gains;
* on the ground, with every drive stiffened to kp 1000 / kd 30, each stands for 5 s on its soles
  alone: the geometry, masses and default pose put the centre of mass over the feet.
"""

from __future__ import annotations

import re

import mujoco
import pytest
import torch

import simlab.sim as sim_utils
from simlab.assets import ArticulationCfg, AssetBaseCfg
from simlab.robots import unitree
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.sensors import ContactSensorCfg
from simlab.utils import configclass

SIDES = ("left", "right")


def _g1_leg(side: str) -> list[str]:
    return [f"{side}_{j}_joint" for j in ("hip_pitch", "hip_roll", "hip_yaw", "knee", "ankle_pitch", "ankle_roll")]


def _g1_hand(side: str) -> list[str]:
    return [f"{side}_{f}_joint" for f in ("zero", "one", "two", "three", "four", "five", "six")]


# MuJoCo's depth-first order: each leg, then the torso and each arm (with its hand).
H1_MODEL_JOINTS = (
    [f"{s}_{j}" for s in SIDES for j in ("hip_yaw", "hip_roll", "hip_pitch", "knee", "ankle")]
    + ["torso"]
    + [f"{s}_{j}" for s in SIDES for j in ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow")]
)
G1_MODEL_JOINTS = (
    _g1_leg("left")
    + _g1_leg("right")
    + ["torso_joint"]
    + [
        joint
        for s in SIDES
        for joint in [
            f"{s}_{j}_joint" for j in ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow_pitch", "elbow_roll")
        ]
        + _g1_hand(s)
    ]
)
G1_29DOF_MODEL_JOINTS = (
    _g1_leg("left")
    + _g1_leg("right")
    + ["waist_yaw_joint", "waist_roll_joint", "waist_pitch_joint"]
    + [
        f"{s}_{j}_joint"
        for s in SIDES
        for j in ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow", "wrist_roll", "wrist_pitch", "wrist_yaw")
    ]
)

# The total mass of the published model (Unitree's description, as mujoco_menagerie and mjlab ship
# it) [kg]. Unitree's spec sheets round: G1 "about 35 kg", H1 "about 47 kg".
PUBLISHED_MASS = {"unitree_h1.xml": 51.437, "unitree_g1.xml": 32.239, "unitree_g1_29dof.xml": 33.341}

ROBOTS = {
    # config: (model file, its joints depth-first, foot bodies, standing base height band [m])
    "H1_CFG": ("unitree_h1.xml", H1_MODEL_JOINTS, ".*_ankle_link", (0.94, 1.0)),
    "G1_CFG": ("unitree_g1.xml", G1_MODEL_JOINTS, ".*_ankle_roll_link", (0.69, 0.74)),
    "G1_29DOF_CFG": ("unitree_g1_29dof.xml", G1_29DOF_MODEL_JOINTS, ".*_ankle_roll_link", (0.73, 0.78)),
}


def level_order(model: mujoco.MjModel) -> list[str]:
    """The hinge joints level by level down the body tree, depth-first within a level (Isaac Lab's order)."""
    depth = [0] * model.nbody
    for b in range(1, model.nbody):
        depth[b] = depth[model.body_parentid[b]] + 1
    joints = [j for j in range(model.njnt) if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE]
    return [model.joint(j).name for j in sorted(joints, key=lambda j: (depth[model.jnt_bodyid[j]], j))]


@pytest.mark.parametrize("config", sorted(ROBOTS))
def test_model_names_order_and_mass(config):
    file, joints, _, _ = ROBOTS[config]
    model = mujoco.MjModel.from_xml_path(unitree.ASSETS_DIR + "/" + file)
    assert model.nu == 0 and model.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE
    assert [model.joint(j).name for j in range(1, model.njnt)] == joints
    assert model.body(1).name == "pelvis" and model.body_parentid[1] == 0
    assert sum(model.body_mass) == pytest.approx(PUBLISHED_MASS[file], rel=0.05)
    assert (model.jnt_limited[1:] == 1).all(), "every joint has its published range"


def scene_with(robot_cfg: ArticulationCfg, engine: str = "mujoco", num_envs: int = 2):
    @configclass
    class SceneCfg(InteractiveSceneCfg):
        ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
        robot: ArticulationCfg = robot_cfg.replace(prim_path="{ENV_REGEX_NS}/Robot")
        contacts = ContactSensorCfg(prim_path="{ENV_REGEX_NS}/Robot/.*")

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device="cpu", engine=engine))
    scene = InteractiveScene(SceneCfg(num_envs=num_envs, env_spacing=3.0))
    sim.reset()
    return sim, scene


def run(sim, scene, steps: int) -> torch.Tensor:
    """Step with the targets at the default pose; the base heights of every step (steps, envs)."""
    robot = scene["robot"]
    robot.set_joint_position_target(robot.data.default_joint_pos)
    heights = []
    for _ in range(steps):
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())
        heights.append(robot.data.root_pos_w[:, 2].clone())
    return torch.stack(heights)


@pytest.mark.parametrize("config", sorted(ROBOTS))
def test_articulation_names_order_and_gains(config):
    cfg = getattr(unitree, config)
    file, joints, _, _ = ROBOTS[config]
    sim, scene = scene_with(cfg)
    robot = scene["robot"]
    assert robot.joint_names == level_order(mujoco.MjModel.from_xml_path(unitree.ASSETS_DIR + "/" + file))
    assert sorted(robot.joint_names) == sorted(joints)
    assert robot.body_names[0] == "pelvis"
    torch.testing.assert_close(robot.data.joint_pos, robot.data.default_joint_pos)
    # every joint is driven by exactly one of the config's groups, with its gains
    assert sorted(j for a in robot.actuators.values() for j in a.joint_names) == sorted(joints)
    assert (robot.data.joint_stiffness > 0).all() and (robot.data.joint_damping > 0).all()


def test_isaac_lab_gains_per_group():
    sim, scene = scene_with(unitree.H1_CFG)
    h1 = scene["robot"]
    kp = dict(zip(h1.joint_names, h1.data.joint_stiffness[0].tolist()))
    kd = dict(zip(h1.joint_names, h1.data.joint_damping[0].tolist()))
    assert (kp["left_hip_yaw"], kp["left_knee"], kp["torso"], kp["left_ankle"], kp["left_elbow"]) == (
        150,
        200,
        200,
        20,
        40,
    )
    assert (kd["left_knee"], kd["left_ankle"], kd["left_elbow"]) == (5, 4, 10)
    limits = dict(zip(h1.joint_names, h1.data.joint_effort_limits[0].tolist()))
    assert (limits["left_knee"], limits["right_ankle"], limits["left_shoulder_yaw"]) == (300, 100, 300)

    sim, scene = scene_with(unitree.G1_CFG)
    g1 = scene["robot"]
    kp = dict(zip(g1.joint_names, g1.data.joint_stiffness[0].tolist()))
    armature = dict(zip(g1.joint_names, g1.data.joint_armature[0].tolist()))
    limits = dict(zip(g1.joint_names, g1.data.joint_effort_limits[0].tolist()))
    assert (kp["left_hip_roll_joint"], kp["torso_joint"], kp["left_ankle_roll_joint"], kp["right_six_joint"]) == (
        150,
        200,
        20,
        40,
    )
    assert limits["left_ankle_pitch_joint"] == 20 and limits["left_knee_joint"] == 300
    assert armature["left_knee_joint"] == pytest.approx(0.01) and armature["left_two_joint"] == pytest.approx(0.001)


def test_g1_29dof_motor_model():
    sim, scene = scene_with(unitree.G1_29DOF_CFG)
    robot = scene["robot"]
    kp = dict(zip(robot.joint_names, robot.data.joint_stiffness[0].tolist()))
    kd = dict(zip(robot.joint_names, robot.data.joint_damping[0].tolist()))
    armature = dict(zip(robot.joint_names, robot.data.joint_armature[0].tolist()))
    limits = dict(zip(robot.joint_names, robot.data.joint_effort_limits[0].tolist()))
    omega = 2 * torch.pi * 10.0
    for joint, (inertia, effort) in {
        "left_knee_joint": (0.025102, 139.0),
        "left_hip_pitch_joint": (0.010178, 88.0),
        "left_elbow_joint": (0.003610, 25.0),
        "left_wrist_yaw_joint": (0.00425, 5.0),
        "right_ankle_roll_joint": (0.007219, 50.0),
        "waist_pitch_joint": (0.007219, 50.0),
    }.items():
        assert armature[joint] == pytest.approx(inertia, rel=1e-4)
        assert kp[joint] == pytest.approx(inertia * omega**2, rel=1e-4)  # a 10 Hz response ...
        assert kd[joint] == pytest.approx(2 * 2.0 * inertia * omega, rel=1e-4)  # ... with damping ratio 2
        assert limits[joint] == effort
        # the action scale, keyed by the groups' joint expressions as mjlab's is
        (scale,) = [v for expr, v in unitree.G1_29DOF_ACTION_SCALE.items() if re.fullmatch(expr, joint)]
        assert scale == pytest.approx(0.25 * effort / kp[joint], rel=1e-4)


def test_g1_motor_model_on_the_hand_version():
    """The velocity tasks' G1: the 29-DoF G1's motors on the same joints of the hand version (torso =
    waist yaw, elbow roll = wrist roll), Isaac Lab's gains on the fingers, action scales by mjlab's rule
    for exactly the 23 joints that walk."""
    sim, scene = scene_with(unitree.G1_MOTOR_MODEL_CFG)
    robot = scene["robot"]
    kp = dict(zip(robot.joint_names, robot.data.joint_stiffness[0].tolist()))
    armature = dict(zip(robot.joint_names, robot.data.joint_armature[0].tolist()))
    limits = dict(zip(robot.joint_names, robot.data.joint_effort_limits[0].tolist()))
    omega = 2 * torch.pi * 10.0
    for joint, (inertia, effort) in {
        "left_knee_joint": (0.025102, 139.0),
        "right_hip_yaw_joint": (0.010178, 88.0),
        "torso_joint": (0.010178, 88.0),
        "left_elbow_roll_joint": (0.003610, 25.0),
        "right_ankle_pitch_joint": (0.007219, 50.0),
    }.items():
        assert armature[joint] == pytest.approx(inertia, rel=1e-4)
        assert kp[joint] == pytest.approx(inertia * omega**2, rel=1e-4)
        assert limits[joint] == effort
    assert kp["left_five_joint"] == 40.0 and armature["left_five_joint"] == pytest.approx(0.001)
    walking = robot.find_joints(unitree.G1_BODY_JOINTS)[1]
    assert len(walking) == 23 and not any(re.search("_(zero|one|two|three|four|five|six)_", j) for j in walking)
    for joint in walking:
        (scale,) = [v for expr, v in unitree.G1_MOTOR_MODEL_ACTION_SCALE.items() if re.fullmatch(expr, joint)]
        assert scale == pytest.approx(0.25 * limits[joint] / kp[joint], rel=1e-4)
    assert unitree.G1_CFG.actuators.keys() == {"legs", "feet", "arms"}, "Isaac Lab's G1_CFG is left as it is"


def hung(cfg: ArticulationCfg) -> ArticulationCfg:
    cfg = cfg.copy()
    cfg.spawn.articulation_props.fix_root_link = True
    cfg.init_state.pos = (0.0, 0.0, 1.5)
    return cfg


# The most a joint of the hung robot sags below its target [rad]: gravity torque over stiffness. mjlab's
# gains put a 10 Hz response on the motors' own inertia and let the limbs sag (the hanging knees most).
HUNG_SAG = {"H1_CFG": 0.06, "G1_CFG": 0.06, "G1_29DOF_CFG": 0.25}


@pytest.mark.parametrize("config", sorted(ROBOTS))
def test_hung_by_its_base_holds_the_default_pose_under_its_own_gains(config):
    sim, scene = scene_with(hung(getattr(unitree, config)))
    robot = scene["robot"]
    run(sim, scene, 1000)  # 5 s
    error = (robot.data.joint_pos - robot.data.default_joint_pos).abs()
    assert error.max() < HUNG_SAG[config], dict(zip(robot.joint_names, error[0].tolist()))
    assert robot.data.joint_vel.abs().max() < 1e-2, "at rest"
    # at rest the drives' torques are gravity's, joint by joint
    drive, gravity = sim.physics.data("qfrc_actuator"), sim.physics.data("qfrc_bias")
    assert gravity.abs().max() > 1.0
    torch.testing.assert_close(drive, gravity, atol=0.05, rtol=0.01)


def stiff(cfg: ArticulationCfg) -> ArticulationCfg:
    cfg = cfg.copy()
    for group in cfg.actuators.values():
        group.stiffness, group.damping, group.effort_limit_sim = 1000.0, 30.0, None
    return cfg


def _stands(config: str, engine: str) -> None:
    _, _, feet, band = ROBOTS[config]
    cfg = stiff(getattr(unitree, config))
    sim, scene = scene_with(cfg, engine)
    robot, contacts = scene["robot"], scene["contacts"]
    heights = run(sim, scene, 1000)  # 5 s
    settled = heights[100:]  # after landing from the configured spawn height
    assert band[0] < settled.min() and settled.max() < band[1], (settled.min(), settled.max())
    assert settled.max() - settled.min() < 0.03, "the base stays within a few cm"
    assert (robot.data.projected_gravity_b[:, 2] < -0.99).all(), "upright"
    foot_ids, _ = contacts.find_bodies(feet)
    touching = contacts.data.net_forces_w.norm(dim=-1) > 1.0
    assert touching[:, foot_ids].all(), "both feet carry the robot"
    assert touching.sum(dim=1).tolist() == [2, 2], "and nothing else touches the ground"
    weight = float(robot.data.default_mass[0].sum()) * 9.81
    torch.testing.assert_close(contacts.data.net_forces_w[..., 2].sum(1), torch.full((2,), weight), rtol=0.02, atol=0.0)


@pytest.mark.parametrize("config", sorted(ROBOTS))
def test_stands_on_its_soles_for_5_s(config):
    _stands(config, "mujoco")


@pytest.mark.slow
@pytest.mark.parametrize("config", sorted(ROBOTS))
def test_stands_on_its_soles_for_5_s_on_mujoco_warp(config):
    pytest.importorskip("mujoco_warp")
    _stands(config, "mujoco_warp")


def test_minimal_configs_are_isaac_labs_names_for_the_same_robots():
    from simlab.robots import G1_MINIMAL_CFG, H1_MINIMAL_CFG

    assert G1_MINIMAL_CFG.spawn.asset_path == unitree.G1_CFG.spawn.asset_path
    assert H1_MINIMAL_CFG.spawn.asset_path == unitree.H1_CFG.spawn.asset_path
    assert G1_MINIMAL_CFG.actuators.keys() == {"legs", "feet", "arms"} == H1_MINIMAL_CFG.actuators.keys()


@pytest.mark.parametrize("config", ["H1_CFG", "G1_CFG"])
def test_isaac_labs_gains_alone_do_not_balance_the_robot(config):
    """Why the standing test stiffens the drives: with the configs' own gains (ankles kp 20) and the
    targets at the default pose, the robot tips over within 3 s (a policy has to balance it)."""
    sim, scene = scene_with(getattr(unitree, config))
    run(sim, scene, 600)  # 3 s
    assert (scene["robot"].data.projected_gravity_b[:, 2] > -0.5).all(), "tilted past 60 degrees"
