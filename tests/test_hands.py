"""The dexterous hands (simlab.robots.allegro, simlab.robots.shadow_hand) and the DexCube they hold.

Names are Isaac Lab's (its in-hand tasks look joints and fingertips up by name); the Shadow Hand's
distal joints follow their middle joints while the hand moves; a grasp posture keeps the cube on the
upturned palm for 5 s of simulated time on the CPU backend.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import torch

import simlab.sim as sim_utils
from simlab.assets import ArticulationCfg, AssetBaseCfg, RigidObjectCfg
from simlab.robots.allegro import ALLEGRO_FINGERTIP_BODIES, ALLEGRO_HAND_CFG
from simlab.robots.dex_cube import DEX_CUBE_SIZE, dex_cube_cfg
from simlab.robots.shadow_hand import SHADOW_HAND_CFG, SHADOW_HAND_COUPLED_JOINTS, SHADOW_HAND_FINGERTIP_BODIES
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.utils import configclass

DT = 1.0 / 120.0  # sim.dt of Isaac Lab's in-hand tasks

# Isaac Lab's actuated_joint_names of the Allegro and Shadow in-hand tasks
ALLEGRO_JOINTS = [f"{finger}_joint_{i}" for finger in ("index", "middle", "ring", "thumb") for i in range(4)]
SHADOW_ACTUATED = (
    ["robot0_WRJ1", "robot0_WRJ0"]
    + [f"robot0_{f}J{i}" for f in ("FF", "MF", "RF") for i in (3, 2, 1)]
    + [f"robot0_LFJ{i}" for i in (4, 3, 2, 1)]
    + [f"robot0_THJ{i}" for i in (4, 3, 2, 1, 0)]
)
SHADOW_JOINTS = SHADOW_ACTUATED + list(SHADOW_HAND_COUPLED_JOINTS)

# (robot config, cube scale and density, cube spawn position, a grasp posture) as Isaac Lab's tasks set them up
HANDS = {
    "allegro": (
        ALLEGRO_HAND_CFG,
        (1.2, 400.0),
        (0.0, -0.17, 0.56),
        {
            "(index|middle|ring)_joint_1": 0.5,
            "(index|middle|ring)_joint_[23]": 0.8,
            "thumb_joint_0": 1.3,
            "thumb_joint_[123]": 0.6,
        },
    ),
    "shadow": (
        SHADOW_HAND_CFG,
        (1.0, 567.0),
        (0.0, -0.39, 0.6),
        {"robot0_(FF|MF|RF|LF)J2": 0.4, "robot0_(FF|MF|RF|LF)J1": 0.6, "robot0_THJ[43]": 1.0, "robot0_THJ0": 0.5},
    ),
}


def make_scene(hand: str, num_envs: int = 1):
    robot_cfg, (scale, density), cube_pos, _ = HANDS[hand]

    @configclass
    class HandSceneCfg(InteractiveSceneCfg):
        ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
        robot: ArticulationCfg = robot_cfg.replace(prim_path="{ENV_REGEX_NS}/Robot")
        object = RigidObjectCfg(
            prim_path="{ENV_REGEX_NS}/object",
            spawn=dex_cube_cfg(scale, density),
            init_state=RigidObjectCfg.InitialStateCfg(pos=cube_pos),
        )

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=DT, device="cpu"))
    scene = InteractiveScene(HandSceneCfg(num_envs=num_envs, env_spacing=0.75))
    sim.reset()
    return sim, scene


def step(sim, scene, n: int = 1):
    for _ in range(n):
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())


def posture(robot, targets: dict[str, float]) -> torch.Tensor:
    pose = robot.data.default_joint_pos.clone()
    for pattern, value in targets.items():
        ids = [i for i, name in enumerate(robot.joint_names) if re.fullmatch(pattern, name)]
        assert ids, pattern
        pose[:, ids] = value
    return pose


def test_allegro_has_isaac_lab_joints_fingertips_and_pose():
    _, scene = make_scene("allegro")
    robot = scene["robot"]
    assert sorted(robot.joint_names) == sorted(ALLEGRO_JOINTS)
    assert robot.find_bodies(ALLEGRO_FINGERTIP_BODIES, preserve_order=True)[1] == ALLEGRO_FINGERTIP_BODIES
    assert robot.is_fixed_base and set(robot.actuators) == {"fingers"}
    torch.testing.assert_close(robot.data.joint_stiffness[0], torch.full((16,), 1.0))  # Isaac Lab 3.x
    torch.testing.assert_close(robot.data.joint_effort_limits[0], torch.full((16,), 0.5))
    thumb = robot.joint_names.index("thumb_joint_0")
    assert robot.data.default_joint_pos[0, thumb] == pytest.approx(0.28)
    # the Allegro URDF's link masses: 0.4154 kg palm, four fingers (thumb 0.1231 kg, others 0.1388 kg)
    assert float(robot.data.default_mass[0].sum()) == pytest.approx(0.4154 + 3 * 0.1388 + 0.1231, abs=1e-4)


def test_allegro_fingers_are_where_isaac_labs_pose_puts_them():
    """Isaac Lab's Allegro and its pose are IsaacGymEnvs' (kuka_allegro_description/allegro.urdf, rooted at
    its mount): the index, middle and ring flexion joints (Allegro joint 1) land at these world points,
    computed from that URDF's allegro_mount_joint and joint origins. The cube, dropped at (0, -0.17, 0.56),
    lands just past them, as in Isaac Lab; a hand 2 cm further back leaves it on the fingers' far half."""
    _, scene = make_scene("allegro")
    robot = scene["robot"]
    expected = {
        "index_link_1": (-0.0451, -0.1326, 0.4966),
        "middle_link_1": (0.0, -0.1349, 0.4964),
        "ring_link_1": (0.0451, -0.1326, 0.4966),
    }
    for body, position in expected.items():
        found = robot.data.body_pos_w[0, robot.body_names.index(body)]
        torch.testing.assert_close(found, torch.tensor(position), atol=2e-3, rtol=0.0, msg=body)


# Joint limits (rad) of IsaacGymEnvs' kuka_allegro_description/allegro.urdf, the description behind Isaac
# Lab's Allegro USD (menagerie's, which the model had before, are 6-16 % narrower)
ALLEGRO_URDF_LIMITS = {
    "(index|middle|ring)_joint_0": (-0.558489, 0.558489),
    "(index|middle|ring)_joint_[123]": (-0.279244, 1.727825),
    "thumb_joint_0": (0.279244, 1.57075),
    "thumb_joint_1": (-0.331603, 1.151883),
    "thumb_joint_2": (-0.279244, 1.727825),
    "thumb_joint_3": (-0.279244, 1.762731),
}


def test_allegro_joint_limits_are_isaacgymenvs_urdfs_and_hold_the_default_pose():
    """Isaac Lab's direct task maps each action onto a joint's range and its manager task scales them to the
    soft limits (factor 1), so the ranges are the action space: they must be the URDF's."""
    _, scene = make_scene("allegro")
    robot = scene["robot"]
    limits = robot.data.joint_pos_limits[0]
    covered = []
    for pattern, (lower, upper) in ALLEGRO_URDF_LIMITS.items():
        ids = [i for i, name in enumerate(robot.joint_names) if re.fullmatch(pattern, name)]
        assert ids, pattern
        covered += ids
        torch.testing.assert_close(limits[ids], torch.tensor([[lower, upper]] * len(ids)), atol=1e-6, rtol=0.0)
    assert sorted(covered) == list(range(16))
    torch.testing.assert_close(robot.data.soft_joint_pos_limits[0], limits)
    default = robot.data.default_joint_pos[0]
    assert ((default >= limits[:, 0]) & (default <= limits[:, 1])).all()  # thumb_joint_0's 0.28 too


def test_allegro_joints_turn_as_the_urdfs_so_its_limits_carry_over():
    """In a flexed, spread pose the last phalanges (the point 3 cm along each from its joint) lie where
    IsaacGymEnvs' allegro.urdf puts them (its joint origins and Isaac Lab's root pose): every joint has the
    URDF's zero and sign, so the URDF's limits mean the same here. The thumb is 2 mm off (menagerie's thumb
    base); any one joint of this pose mirrored moves a point 2.4 cm or more."""
    import mujoco

    sim, scene = make_scene("allegro")
    model, robot = sim.model, scene["robot"]
    data = mujoco.MjData(model)
    pose = posture(
        robot,
        {
            "(index|middle|ring)_joint_0": 0.3,
            "(index|middle|ring)_joint_[123]": 0.8,
            "thumb_joint_0": 1.2,
            "thumb_joint_[123]": 0.6,
        },
    )
    data.qpos[robot._qpos_cols] = pose[0].numpy()
    mujoco.mj_kinematics(model, data)
    expected = {
        "index_link_3": (-0.0750, -0.1531, 0.5881),
        "middle_link_3": (-0.0288, -0.1579, 0.5877),
        "ring_link_3": (0.0177, -0.1581, 0.5877),
        "thumb_link_3": (-0.0257, -0.1001, 0.5967),
    }
    for body, position in expected.items():
        b = model.body(f"Robot/{body}").id
        along = data.xmat[b].reshape(3, 3)[:, 2]  # the phalanx's axis in this model (the URDF's is its x)
        found = torch.tensor(data.xpos[b] + 0.03 * along, dtype=torch.float32)
        torch.testing.assert_close(found, torch.tensor(position), atol=3e-3, rtol=0.0, msg=body)


def test_shadow_hand_has_isaac_lab_joints_fingertips_and_20_actuated_joints():
    _, scene = make_scene("shadow")
    robot = scene["robot"]
    assert sorted(robot.joint_names) == sorted(SHADOW_JOINTS)
    assert robot.find_bodies(SHADOW_HAND_FINGERTIP_BODIES, preserve_order=True)[1] == SHADOW_HAND_FINGERTIP_BODIES
    assert sorted(robot.actuators["fingers"].joint_names) == sorted(SHADOW_ACTUATED)
    stiffness = dict(zip(robot.joint_names, robot.data.joint_stiffness[0].tolist()))
    assert stiffness["robot0_WRJ1"] == 5.0 and stiffness["robot0_FFJ1"] == 1.0
    assert all(stiffness[distal] == 0.0 for distal in SHADOW_HAND_COUPLED_JOINTS)  # driven by the coupling only
    effort = dict(zip(robot.joint_names, robot.data.joint_effort_limits[0].tolist()))
    assert effort["robot0_THJ4"] == pytest.approx(2.3722) and effort["robot0_FFJ1"] == pytest.approx(0.7245)


def test_shadow_distal_joints_follow_the_middle_joints_while_they_move():
    sim, scene = make_scene("shadow")
    robot = scene["robot"]
    middle = [robot.joint_names.index(j) for j in SHADOW_HAND_COUPLED_JOINTS.values()]
    distal = [robot.joint_names.index(j) for j in SHADOW_HAND_COUPLED_JOINTS]
    worst, travelled = 0.0, torch.zeros(4)
    for target in (1.4, 0.2, 1.0):  # flex, open, flex again: 0.5 s each
        robot.set_joint_position_target(posture(robot, {"robot0_(FF|MF|RF|LF)J1": target}))
        for _ in range(60):
            before = robot.data.joint_pos[0, middle].clone()
            step(sim, scene)
            travelled += (robot.data.joint_pos[0, middle] - before).abs()
            gap = (robot.data.joint_pos[0, distal] - robot.data.joint_pos[0, middle]).abs().max()
            worst = max(worst, float(gap))
    assert (travelled > 2.0).all(), travelled  # the middle joints really moved (1.2 + 0.8 rad and more)
    assert worst < 0.02, worst


@pytest.mark.parametrize("hand", list(HANDS))
def test_a_grasp_posture_holds_the_cube_on_the_upturned_palm_for_5_s(hand):
    sim, scene = make_scene(hand)
    robot, cube = scene["robot"], scene["object"]
    robot.set_joint_position_target(posture(robot, HANDS[hand][3]))
    step(sim, scene, 60)  # the fingers close and the cube settles (0.5 s)
    settled = cube.data.root_pos_w[0].clone()
    palm_height = float(robot.data.root_pos_w[0, 2])
    for _ in range(10):
        step(sim, scene, 60)
        position = cube.data.root_pos_w[0]
        assert torch.isfinite(position).all()
        assert float(position[2]) > palm_height + DEX_CUBE_SIZE / 2  # above the palm, not beside or below it
        assert float((position - settled).norm()) < 0.02  # held: it neither slides nor rolls away
    assert float(cube.data.root_lin_vel_w[0].norm()) < 0.01


@pytest.mark.parametrize("hand", list(HANDS))
def test_hands_collide_with_themselves_but_not_in_their_default_pose(hand):
    """Self collisions are on (as Isaac Lab's configs enable them); the pairs that overlap by design are
    excluded, so the default pose touches nothing."""
    import mujoco
    import numpy as np

    sim, scene = make_scene(hand)
    model, robot = sim.model, scene["robot"]
    data = mujoco.MjData(model)
    hand_bodies = {model.body(f"Robot/{name}").id for name in robot.body_names}

    def self_contacts(joint_pos: np.ndarray) -> int:
        data.qpos[robot._qpos_cols] = joint_pos
        mujoco.mj_forward(model, data)
        pairs = [(model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]) for c in data.contact[: data.ncon]]
        return sum(b1 in hand_bodies and b2 in hand_bodies for b1, b2 in pairs)

    assert self_contacts(robot.data.default_joint_pos[0].numpy()) == 0
    limits = robot.data.joint_pos_limits[0].numpy()
    rng = np.random.default_rng(0)
    touching = sum(self_contacts(rng.uniform(limits[:, 0], limits[:, 1])) > 0 for _ in range(50))
    assert touching > 5  # random poses press fingers into each other or into the palm


@pytest.mark.parametrize(("stiffness", "friction", "falls"), [(1.0, 1e-4, False), (3.0, 0.01, True)])
def test_allegro_keeps_the_cube_under_zero_actions_at_isaac_lab_3s_gains(stiffness, friction, falls):
    """Zero actions put every joint target mid-range. With Isaac Lab 3.x's gains (kp 1, friction 1e-4, the
    config's) the hand keeps the cube for 40 env steps; Isaac Lab 2.x's kp 3 and friction 0.01 curl the
    fingers hard enough to throw it off the palm (docs/dexterous.md: after 13 steps on average)."""
    import gymnasium as gym
    from conftest import load_script

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.tasks.utils import parse_env_cfg

    tool = load_script(Path(__file__).parents[1] / "scripts" / "tools" / "inhand_cube_falls.py")
    task = "simlab/Repose-Cube-Allegro-Direct-v0"
    cfg = parse_env_cfg(task, device="cpu", num_envs=8)
    cfg.seed = 42
    fingers = cfg.robot_cfg.actuators["fingers"]
    assert (fingers.stiffness, fingers.friction) == (1.0, 1e-4)  # the config is Isaac Lab 3.x's
    fingers.stiffness, fingers.friction = stiffness, friction
    env = gym.make(task, cfg=cfg).unwrapped
    try:
        result = tool.cube_falls(env, "zero", steps=40, seed=42)
    finally:
        env.close()
    assert (result.falls >= 3) if falls else (result.falls == 0), result
