"""Agility Digit V4: the MJCF model, DIGIT_V4_CFG, its closed loops, and the velocity tasks.

The model has the 32 joints of Isaac Lab's digit_v4.usd less its rods' ball joints; each leg's three
rods (the achilles rod, which makes the tarsus follow the knee, and the toe A and B rods, which set the
foot's pitch and roll from the two toe motors) are fixed-length tendons held by equality constraints.
Checked here: the names, the order (Isaac Lab's, level by level), the mass, that the loops hold (under a
millimetre) while the motors sweep their ranges and while standing, that the robot stands on its soles
under stiff drives and hangs in its default pose under its own gains (which leave balancing to the
policy, as for G1, H1 and Cassie), and that the tasks and Isaac Lab's own task files run.
"""

from __future__ import annotations

import importlib
import math
import sys
from pathlib import Path

import gymnasium as gym
import mujoco
import pytest
import torch
from test_humanoid_robots import hung, scene_with, stiff

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.envs import ManagerBasedRLEnv
from simlab.robots import DIGIT_V4_CFG, agility
from simlab.robots.agility import DIGIT_V4_MOTOR_MODEL_ACTION_SCALE, DIGIT_V4_MOTOR_MODEL_CFG
from simlab.tasks.utils.parse_cfg import parse_env_cfg

MODEL = agility.ASSETS_DIR + "/agility_digit.xml"
SIDES = ("left", "right")
LEG = ("hip_roll", "hip_yaw", "hip_pitch", "knee", "tarsus", "toe_a", "toe_b", "toe_pitch", "toe_roll")
ARM = ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow", "wrist_roll", "wrist_pitch", "wrist_yaw")
# MuJoCo's depth-first order: left leg, left arm, right leg, right arm
MODEL_JOINTS = [j for s in SIDES for j in [f"{s}_leg_{n}" for n in LEG] + [f"{s}_arm_{n}" for n in ARM]]
# Isaac Lab's (PhysX's level by level) for digit_v4.usd, less the rods' ball joints (<rod>:0..2)
ISAAC_LAB_JOINTS = [
    "left_leg_hip_roll", "left_arm_shoulder_pitch", "right_leg_hip_roll", "right_arm_shoulder_pitch",
    "left_leg_hip_yaw", "left_arm_shoulder_roll", "right_leg_hip_yaw", "right_arm_shoulder_roll",
    "left_leg_hip_pitch", "left_arm_shoulder_yaw", "right_leg_hip_pitch", "right_arm_shoulder_yaw",
    "left_leg_knee", "left_arm_elbow", "right_leg_knee", "right_arm_elbow",
    "left_leg_tarsus", "left_arm_wrist_roll", "right_leg_tarsus", "right_arm_wrist_roll",
    "left_leg_toe_a", "left_leg_toe_b", "left_leg_toe_pitch", "left_arm_wrist_pitch",
    "right_leg_toe_a", "right_leg_toe_b", "right_leg_toe_pitch", "right_arm_wrist_pitch",
    "left_leg_toe_roll", "left_arm_wrist_yaw", "right_leg_toe_roll", "right_arm_wrist_yaw",
]  # fmt: skip
PASSIVE = [j for j in ISAAC_LAB_JOINTS if j.endswith(("_tarsus", "_toe_pitch", "_toe_roll"))]
MODEL_MASS = 47.925  # Agility's digit-v3 MJCF, the sum of its links [kg]
PUBLISHED_MASS = 48.0  # Digit, as the issue gives it [kg]
RODS = {"achilles_rod": 0.5012, "toe_a_rod": 0.3400, "toe_b_rod": 0.2880}  # ball centre to ball centre [m]
ROD_LENGTHS = torch.tensor([RODS[r] for _ in SIDES for r in RODS])
N = 2


def rod_error(sim) -> torch.Tensor:
    """How far each rod is from its length [m], (envs, 6)."""
    return (sim.physics.data("ten_length") - ROD_LENGTHS).abs()


def step(sim, scene, steps: int, targets=None, each=None) -> None:
    robot = scene["robot"]
    for i in range(steps):
        robot.set_joint_position_target(robot.data.default_joint_pos if targets is None else targets(i))
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())
        if each:
            each(i)


def test_model_names_mass_and_loops():
    model = mujoco.MjModel.from_xml_path(MODEL)
    assert model.nu == 0 and model.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE
    assert [model.joint(j).name for j in range(1, model.njnt)] == MODEL_JOINTS
    assert (model.jnt_type[1:] == mujoco.mjtJoint.mjJNT_HINGE).all() and (model.jnt_limited[1:] == 1).all()
    assert model.body(1).name == "torso_base"
    assert sum(model.body_mass) == pytest.approx(MODEL_MASS, abs=1e-3)
    assert sum(model.body_mass) == pytest.approx(PUBLISHED_MASS, rel=0.05)
    # three equalities per leg, each on a two-site tendon of its rod's length at the reference pose
    assert model.neq == 6 and (model.eq_type == mujoco.mjtEq.mjEQ_TENDON).all()
    assert [model.tendon(t).name for t in range(model.ntendon)] == [f"{s}_leg_{r}" for s in SIDES for r in RODS]
    assert model.tendon_length0 == pytest.approx(ROD_LENGTHS.tolist(), abs=1e-4)
    # Agility's ranges, in radians: the knee -71..50 deg (left), the toe motors -55.4..51.3 and -52.3..72.45
    assert model.joint("left_leg_knee").range == pytest.approx([math.radians(-71), math.radians(50)])
    assert model.joint("right_leg_knee").range == pytest.approx([math.radians(-50), math.radians(71)])
    assert model.joint("left_leg_toe_b").range == pytest.approx([math.radians(-52.3), math.radians(72.45)])


def test_articulation_names_order_gains_and_default_pose():
    sim, scene = scene_with(DIGIT_V4_CFG)
    robot = scene["robot"]
    assert robot.joint_names == ISAAC_LAB_JOINTS
    assert robot.body_names[0] == "torso_base"
    assert {"left_leg_toe_roll", "left_leg_achilles_rod", "right_leg_toe_b_rod", "left_arm_wrist_yaw"} <= set(
        robot.body_names
    )
    torch.testing.assert_close(robot.data.joint_pos, robot.data.default_joint_pos)
    kp = dict(zip(robot.joint_names, robot.data.joint_stiffness[0].tolist()))
    kd = dict(zip(robot.joint_names, robot.data.joint_damping[0].tolist()))
    limits = dict(zip(robot.joint_names, robot.data.joint_effort_limits[0].tolist()))
    leg = {j: kp[f"left_leg_{j}"] for j in ("hip_roll", "hip_yaw", "hip_pitch", "knee", "toe_a", "toe_b")}
    assert leg == {"hip_roll": 100, "hip_yaw": 100, "hip_pitch": 200, "knee": 200, "toe_a": 20, "toe_b": 20}
    arm = {j: kp[f"right_arm_{j}"] for j in ("shoulder_pitch", "shoulder_yaw", "elbow", "wrist_yaw")}
    assert arm == {"shoulder_pitch": 150, "shoulder_yaw": 100, "elbow": 100, "wrist_yaw": 20}
    assert (kd["left_leg_knee"], kd["right_leg_toe_a"], kd["left_arm_shoulder_roll"]) == (5, 1, 5)
    assert (limits["left_leg_hip_roll"], limits["right_leg_hip_pitch"], limits["left_leg_toe_b"]) == (112, 200, 45)
    # one group drives the 26 motors (Isaac Lab's LEG_JOINT_NAMES + ARM_JOINT_NAMES); the rods move the rest
    assert list(robot.actuators) == ["all"]
    assert sorted(robot.actuators["all"].joint_names) == sorted(set(ISAAC_LAB_JOINTS) - set(PASSIVE))
    assert all(kp[j] == 0 and kd[j] == 0 for j in PASSIVE)
    # the default pose closes the loops; the legs mirror each other
    assert rod_error(sim).max() < 2e-4
    pose = dict(zip(robot.joint_names, robot.data.default_joint_pos[0].tolist()))
    assert all(pose[f"left_leg_{j}"] == -pose[f"right_leg_{j}"] for j in LEG)


def test_loops_hold_while_the_motors_sweep_their_ranges():
    """Hung by the torso, every motor follows a sine across half its soft range at 0.5 Hz for 3 s under
    DIGIT_V4_CFG's gains; the tarsus and the foot, moved only by the rods, follow."""
    sim, scene = scene_with(hung(DIGIT_V4_CFG))
    robot = scene["robot"]
    low, high = robot.data.soft_joint_pos_limits[0, :, 0], robot.data.soft_joint_pos_limits[0, :, 1]
    mid, half = (low + high) / 2, (high - low) / 2
    passive = robot.find_joints(PASSIVE, preserve_order=True)[0]
    phase = 0.7 * torch.arange(robot.num_joints)
    worst, seen = [0.0], []

    def targets(i: int) -> torch.Tensor:
        t = i * sim.get_physics_dt()
        sweep = mid + 0.5 * half * torch.sin(math.pi * t + phase)
        ramp = min(1.0, t / 0.5)  # from the default pose into the sweep over 0.5 s
        return robot.data.default_joint_pos + ramp * (sweep - robot.data.default_joint_pos)

    def record(i: int) -> None:
        worst[0] = max(worst[0], float(rod_error(sim).max()))
        seen.append(robot.data.joint_pos[0, passive].clone())

    step(sim, scene, 600, targets, record)  # 3 s
    seen = torch.stack(seen)
    swing = dict(zip(PASSIVE, (seen.max(0).values - seen.min(0).values).tolist()))
    assert min(swing[f"{s}_leg_tarsus"] for s in SIDES) > 0.5, swing
    assert min(swing[f"{s}_leg_toe_{a}"] for s in SIDES for a in ("pitch", "roll")) > 0.2, swing
    assert worst[0] < 1e-3, worst[0]


def test_hung_by_its_torso_holds_the_default_pose_under_its_own_gains():
    sim, scene = scene_with(hung(DIGIT_V4_CFG))
    robot = scene["robot"]
    step(sim, scene, 600)  # 3 s
    error = (robot.data.joint_pos - robot.data.default_joint_pos).abs()
    assert error.max() < 0.05, dict(zip(robot.joint_names, error[0].tolist()))
    assert robot.data.joint_vel.abs().max() < 1e-2, "at rest"


def _stands(engine: str) -> None:
    sim, scene = scene_with(stiff(DIGIT_V4_CFG), engine)
    robot, contacts = scene["robot"], scene["contacts"]
    heights, worst = [], [0.0]

    def record(i: int) -> None:
        heights.append(robot.data.root_pos_w[:, 2].clone())
        if i >= 100:  # after landing from 13 mm
            worst[0] = max(worst[0], float(rod_error(sim).max()))

    step(sim, scene, 600, each=record)  # 3 s
    settled = torch.stack(heights)[100:]
    assert settled.min() > 1.0 and settled.max() < 1.03, (settled.min(), settled.max())
    assert (robot.data.projected_gravity_b[:, 2] < -0.99).all(), "upright"
    assert worst[0] < 1e-3, "the rods hold the weight"
    feet, _ = contacts.find_bodies(".*_leg_toe_roll")
    touching = contacts.data.net_forces_w.norm(dim=-1) > 1.0
    assert touching[:, feet].all() and touching.sum(dim=1).tolist() == [2] * N, "the soles alone carry it"
    weight = float(robot.data.default_mass[0].sum()) * 9.81
    torch.testing.assert_close(
        contacts.data.net_forces_w[:, feet, 2].sum(1), torch.full((N,), weight), rtol=0.02, atol=0
    )


def test_stands_on_its_soles_under_stiff_drives():
    _stands("mujoco")


@pytest.mark.slow
def test_stands_on_its_soles_under_stiff_drives_on_mujoco_warp():
    pytest.importorskip("mujoco_warp")
    _stands("mujoco_warp")


def test_its_own_gains_alone_do_not_hold_it_up():
    """Why the standing test stiffens the drives: under DIGIT_V4_CFG's gains, targets at the default
    pose, the robot tips over within 2 s (a policy has to balance it)."""
    sim, scene = scene_with(DIGIT_V4_CFG)
    step(sim, scene, 400)  # 2 s
    assert (scene["robot"].data.root_pos_w[:, 2] < 0.5).all()


def test_motor_model_gains_put_each_motors_reflected_inertia_at_10_hz():
    """DIGIT_V4_MOTOR_MODEL_CFG's table of armatures is the MJCF's: kp = armature (20 pi)^2 and kd = 4
    armature 20 pi on every motor, as read back from the built articulation; the passive joints get none."""
    sim, scene = scene_with(DIGIT_V4_MOTOR_MODEL_CFG)
    robot = scene["robot"]
    omega = 2 * math.pi * 10
    armature, kp, kd = (robot.data.joint_armature[0], robot.data.joint_stiffness[0], robot.data.joint_damping[0])
    for j, name in enumerate(robot.joint_names):
        if name in PASSIVE:
            assert kp[j] == 0 and kd[j] == 0, name
        else:
            assert float(kp[j]) == pytest.approx(float(armature[j]) * omega**2, rel=1e-5), name
            assert float(kd[j]) == pytest.approx(4 * float(armature[j]) * omega, rel=1e-5), name
    knee = robot.joint_names.index("left_leg_knee")
    assert float(kp[knee]) == pytest.approx(476.0, abs=0.1)
    # mjlab's action scale: a unit of action asks a quarter of the effort limit
    assert DIGIT_V4_MOTOR_MODEL_ACTION_SCALE[".*_knee"] == pytest.approx(0.25 * 200.0 / float(kp[knee]), rel=1e-5)


@pytest.mark.parametrize("config, give", [("DIGIT_V4_CFG", (0.5, 0.8)), ("DIGIT_V4_MOTOR_MODEL_CFG", (0.1, 0.2))])
def test_how_far_the_knees_give_under_the_robots_weight(config, give):
    """Targets at the default pose, landing from 13 mm: kp 200 / kd 5 let the knees give 0.62 rad within
    0.5 s (the robot crouches before it tips); the motor model's 476 / 30, 0.16 rad."""
    sim, scene = scene_with(getattr(agility, config))
    robot = scene["robot"]
    knees = robot.find_joints(".*_leg_knee")[0]
    worst = [0.0]

    def record(i: int) -> None:
        deflection = robot.data.joint_pos[:, knees] - robot.data.default_joint_pos[:, knees]
        worst[0] = max(worst[0], float(deflection.abs().max()))

    step(sim, scene, 100, each=record)  # 0.5 s
    assert give[0] < worst[0] < give[1], worst[0]


def make(task: str) -> ManagerBasedRLEnv:
    cfg = parse_env_cfg(task, device="cpu", num_envs=N)
    cfg.seed = 0
    return gym.make(task, cfg=cfg).unwrapped


def steps_finite(env: ManagerBasedRLEnv, steps: int = 20) -> None:
    obs, _ = env.reset()
    for _ in range(steps):
        obs, reward, *_ = env.step(0.3 * torch.randn(N, env.action_manager.total_action_dim))
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()


@pytest.mark.parametrize("task", ["Flat", "Rough", "Flat-Play", "Rough-Play"])
def test_task_builds_and_steps(task):
    terrain, _, play = task.partition("-")
    task_id = f"simlab/Velocity-{terrain}-Digit{'-' + play if play else ''}-v0"
    assert (
        gym.spec(task_id)
        .kwargs["success_criterion_entry_point"]
        .startswith("simlab.tasks.manager_based.locomotion.velocity.criterion:")
    )
    env = make(task_id)
    try:
        assert env.action_manager.total_action_dim == 26
        # 9 (base velocities, gravity) + 3 (command) + 3 x 26 motors, + the height scan on rough ground
        assert env.observation_manager.group_obs_dim["policy"][0] == 90 + (17 * 11 if terrain == "Rough" else 0)
        steps_finite(env)
    finally:
        env.close()


def test_flat_task_stands_1_4_s_on_zero_actions():
    """The policy's starting point: with zero actions (targets at the default pose) every robot stands
    74 steps (1.48 s) before it tips past 40 degrees. Isaac Lab's settings (kp 200 / kd 5, a reset
    that throws the robot at up to 0.5 m/s and 0.5 rad/s) ended them after 34-50 steps."""
    env = make("simlab/Velocity-Flat-Digit-v0")
    try:
        env.reset()
        first = torch.zeros(N, dtype=torch.long)
        for i in range(90):
            _, _, terminated, _, _ = env.step(torch.zeros(N, env.action_manager.total_action_dim))
            first[(first == 0) & terminated] = i + 1
        assert (first >= 70).all(), first.tolist()
    finally:
        env.close()


def ported(terrain: str):
    path = str(Path(__file__).parent / "ported")
    sys.path.insert(0, path)
    try:
        module = importlib.import_module(f"isaaclab_velocity_digit.{terrain.lower()}_env_cfg")
    finally:
        sys.path.remove(path)
    return getattr(module, f"Digit{terrain}EnvCfg")()


@pytest.mark.parametrize("terrain", ["Flat", "Rough"])
def test_isaac_labs_own_task_config_runs_after_the_import_mapping(terrain):
    cfg = ported(terrain)
    ours = parse_env_cfg(f"simlab/Velocity-{terrain}-Digit-v0", device="cpu", num_envs=N)
    # the same terms and weights, but for the tracking weights simlab raises for MuJoCo (rough_env_cfg.py)
    weights = {name: term.weight for name, term in vars(cfg.rewards).items() if term is not None}
    retuned = {"track_lin_vel_xy_exp": 2.0, "track_ang_vel_z_exp": 2.0}
    assert {name: term.weight for name, term in vars(ours.rewards).items() if term is not None} == {
        **weights,
        **retuned,
    }
    # Isaac Lab's file leaves the centre-of-mass event on a body named "base", which Digit lacks (its
    # root is torso_base); simlab's task turns it off, as for its other bipeds.
    cfg.events.base_com = None
    cfg.scene.num_envs, cfg.sim.device, cfg.seed = N, "cpu", 0
    env = ManagerBasedRLEnv(cfg)
    try:
        assert env.action_manager.total_action_dim == 26
        steps_finite(env, 5)
    finally:
        env.close()
