"""The MDP term library on a floating-base robot (the ant), a box and contact sensors."""

from __future__ import annotations

import math

import pytest
import torch

import simlab.envs.mdp as mdp
import simlab.sim as sim_utils
import simlab.utils.math as math_utils
from simlab.assets import ArticulationCfg, AssetBaseCfg, RigidObjectCfg
from simlab.envs import ManagerBasedRLEnv, ManagerBasedRLEnvCfg
from simlab.managers import ObservationGroupCfg as ObsGroup
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.managers import RewardTermCfg as RewTerm
from simlab.managers import SceneEntityCfg
from simlab.managers import TerminationTermCfg as DoneTerm
from simlab.robots.ant import ANT_CFG
from simlab.scene import InteractiveSceneCfg
from simlab.sensors import ContactSensorCfg
from simlab.utils import configclass

N = 4
BOX_MASS = 2.0
ROBOT = SceneEntityCfg("robot")
BOX = SceneEntityCfg("box")


@configclass
class SceneCfg(InteractiveSceneCfg):
    ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
    robot: ArticulationCfg = ANT_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
    box = RigidObjectCfg(
        prim_path="{ENV_REGEX_NS}/Box",
        spawn=sim_utils.CuboidCfg(
            size=(0.2, 0.2, 0.2),
            rigid_props=sim_utils.RigidBodyPropertiesCfg(),
            mass_props=sim_utils.MassPropertiesCfg(mass=BOX_MASS),
        ),
        init_state=RigidObjectCfg.InitialStateCfg(pos=(2.0, 0.0, 0.1)),
    )
    robot_contacts = ContactSensorCfg(prim_path="{ENV_REGEX_NS}/Robot/.*", history_length=3, track_air_time=True)
    box_contact = ContactSensorCfg(prim_path="{ENV_REGEX_NS}/Box/.*")


@configclass
class ObservationsCfg:
    @configclass
    class PolicyCfg(ObsGroup):
        base_lin_vel = ObsTerm(func=mdp.base_lin_vel)
        projected_gravity = ObsTerm(func=mdp.projected_gravity)
        joint_pos = ObsTerm(func=mdp.joint_pos_limit_normalized)
        actions = ObsTerm(func=mdp.last_action)

    policy: PolicyCfg = PolicyCfg()


@configclass
class ActionsCfg:
    joints = mdp.JointEffortActionCfg(asset_name="robot", joint_names=[".*"], scale=15.0)


@configclass
class RewardsCfg:
    alive = RewTerm(func=mdp.is_alive, weight=1.0)


@configclass
class TerminationsCfg:
    time_out = DoneTerm(func=mdp.time_out, time_out=True)


@configclass
class AntEnvCfg(ManagerBasedRLEnvCfg):
    scene = SceneCfg(num_envs=N, env_spacing=5.0)
    observations = ObservationsCfg()
    actions = ActionsCfg()
    rewards = RewardsCfg()
    terminations = TerminationsCfg()

    def __post_init__(self):
        self.decimation = 4
        self.episode_length_s = 10.0
        self.sim.dt = 0.005
        self.sim.device = "cpu"
        self.seed = 0


@pytest.fixture
def env():
    env = ManagerBasedRLEnv(AntEnvCfg())
    env.reset()
    yield env
    env.close()


def resolved(env, cfg: SceneEntityCfg) -> SceneEntityCfg:
    cfg = cfg.copy()
    cfg.resolve(env.scene)
    return cfg


def set_root(env, quat=(1.0, 0.0, 0.0, 0.0), height=0.8, lin_vel=(0.0, 0.0, 0.0), ang_vel=(0.0, 0.0, 0.0)):
    robot = env.scene["robot"]
    state = torch.tensor([[0.0, 0.0, height, *quat, *lin_vel, *ang_vel]]).repeat(N, 1)
    state[:, :3] += env.scene.env_origins
    robot.write_root_state_to_sim(state)
    env.sim.forward()


def settle(env, steps: int = 50):
    for _ in range(steps):
        env.step(torch.zeros(N, 8))


# -- observations ----------------------------------------------------------------------------------


def test_root_observations_in_the_right_frames(env):
    yaw90 = (math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4))
    set_root(env, quat=yaw90, height=0.9, lin_vel=(1.0, 0.0, 0.5), ang_vel=(0.0, 0.0, 2.0))
    torch.testing.assert_close(mdp.base_pos_z(env), torch.full((N, 1), 0.9))
    torch.testing.assert_close(mdp.root_pos_w(env), torch.tensor([[0.0, 0.0, 0.9]]).repeat(N, 1), atol=1e-6, rtol=0)
    # World +x is the body's -y after a 90 deg yaw.
    torch.testing.assert_close(mdp.base_lin_vel(env), torch.tensor([[0.0, -1.0, 0.5]]).repeat(N, 1), atol=1e-5, rtol=0)
    torch.testing.assert_close(mdp.base_ang_vel(env), torch.tensor([[0.0, 0.0, 2.0]]).repeat(N, 1), atol=1e-5, rtol=0)
    torch.testing.assert_close(mdp.root_lin_vel_w(env), torch.tensor([[1.0, 0.0, 0.5]]).repeat(N, 1))
    torch.testing.assert_close(
        mdp.projected_gravity(env), torch.tensor([[0.0, 0.0, -1.0]]).repeat(N, 1), atol=1e-6, rtol=0
    )
    neg = mdp.root_quat_w(env) * -1
    env.scene["robot"].write_root_pose_to_sim(torch.cat([env.scene["robot"].data.root_pos_w, neg], dim=1))
    assert (mdp.root_quat_w(env, make_quat_unique=True)[:, 0] >= 0).all()


def test_body_and_time_observations(env):
    yaw90 = (math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4))
    set_root(env, quat=yaw90, height=0.9)
    torso = resolved(env, SceneEntityCfg("robot", body_names=["torso"]))
    pose = mdp.body_pose_w(env, asset_cfg=torso)
    assert pose.shape == (N, 7)
    torch.testing.assert_close(pose[:, :3], torch.tensor([[0.0, 0.0, 0.9]]).repeat(N, 1), atol=1e-6, rtol=0)
    torch.testing.assert_close(pose[:, 3:], torch.tensor([yaw90]).repeat(N, 1), atol=1e-6, rtol=0)
    legs = resolved(env, SceneEntityCfg("robot", body_names=["torso", "front_left_leg"]))
    gravity = mdp.body_projected_gravity_b(env, asset_cfg=legs).reshape(N, 2, 3)
    torch.testing.assert_close(gravity[:, 0], mdp.projected_gravity(env))  # the torso is the root
    torch.testing.assert_close(gravity.norm(dim=-1), torch.ones(N, 2))
    env.episode_length_buf[:] = torch.tensor([0, 1, 10, 20])
    torch.testing.assert_close(mdp.current_time_s(env), env.episode_length_buf.unsqueeze(1) * env.step_dt)
    torch.testing.assert_close(mdp.remaining_time_s(env), 10.0 - mdp.current_time_s(env))


def test_joint_observations(env):
    robot = env.scene["robot"]
    limits = robot.data.soft_joint_pos_limits
    pos = limits[..., 1].clone()
    pos[:, 0] = limits[:, 0, 0]
    robot.write_joint_state_to_sim(pos, torch.ones_like(pos))
    normalized = mdp.joint_pos_limit_normalized(env)
    assert normalized[:, 0].allclose(torch.full((N,), -1.0)) and normalized[:, 1:].allclose(torch.ones(N, 7))
    torch.testing.assert_close(mdp.joint_pos_rel(env), pos - robot.data.default_joint_pos)
    torch.testing.assert_close(mdp.joint_vel_rel(env), torch.ones(N, 8))
    legs = resolved(env, SceneEntityCfg("robot", joint_names=[".*_leg"]))
    assert mdp.joint_pos(env, legs).shape == (N, 4)
    env.step(torch.full((N, 8), 0.5))
    torch.testing.assert_close(mdp.last_action(env), torch.full((N, 8), 0.5))
    torch.testing.assert_close(mdp.last_action(env, "joints"), torch.full((N, 8), 0.5))
    effort = mdp.joint_effort(env)
    assert effort.shape == (N, 8) and effort.abs().max() > 1.0  # 7.5 N m commanded, 30 N m limit


# -- rewards ---------------------------------------------------------------------------------------


def test_root_rewards(env):
    tilt = math_utils.quat_from_euler_xyz(torch.tensor([0.3]), torch.tensor([0.0]), torch.tensor([0.0]))[0].tolist()
    set_root(env, quat=tilt, height=0.5, lin_vel=(0.0, 0.0, 2.0), ang_vel=(1.0, -1.0, 3.0))
    torch.testing.assert_close(mdp.flat_orientation_l2(env), torch.full((N,), math.sin(0.3) ** 2), atol=1e-5, rtol=0)
    torch.testing.assert_close(mdp.base_height_l2(env, target_height=0.8), torch.full((N,), 0.09), atol=1e-5, rtol=0)
    vel_b = math_utils.quat_apply_inverse(
        env.scene["robot"].data.root_quat_w, torch.tensor([[0.0, 0.0, 2.0]]).repeat(N, 1)
    )
    torch.testing.assert_close(mdp.lin_vel_z_l2(env), vel_b[:, 2] ** 2)
    ang_b = env.scene["robot"].data.root_ang_vel_b
    torch.testing.assert_close(mdp.ang_vel_xy_l2(env), (ang_b[:, :2] ** 2).sum(1))


def test_joint_and_action_rewards(env):
    robot = env.scene["robot"]
    default = robot.data.default_joint_pos
    pos = default.clone()
    pos[:, 0] += 0.1
    pos[:, 1] = robot.data.soft_joint_pos_limits[:, 1, 1] + 0.2  # beyond the upper limit
    robot.write_joint_state_to_sim(pos, torch.full_like(pos, -2.0))
    torch.testing.assert_close(mdp.joint_deviation_l1(env), (pos - default).abs().sum(1))
    torch.testing.assert_close(mdp.joint_pos_limits(env), torch.full((N,), 0.2), atol=1e-5, rtol=0)
    torch.testing.assert_close(mdp.joint_vel_l1(env, resolved(env, ROBOT)), torch.full((N,), 16.0))
    torch.testing.assert_close(mdp.joint_vel_l2(env), torch.full((N,), 32.0))
    env.action_manager.process_action(torch.full((N, 8), 1.0))
    env.action_manager.process_action(torch.full((N, 8), 0.5))
    torch.testing.assert_close(mdp.action_l2(env), torch.full((N,), 2.0))
    torch.testing.assert_close(mdp.action_rate_l2(env), torch.full((N,), 2.0))
    assert (mdp.joint_torques_l2(env) >= 0).all()


def test_velocity_tracking_rewards(env):
    @configclass
    class Commands:
        vel = mdp.UniformVelocityCommandCfg(
            asset_name="robot",
            resampling_time_range=(10.0, 10.0),
            ranges=mdp.UniformVelocityCommandCfg.Ranges(
                lin_vel_x=(1.0, 1.0), lin_vel_y=(0.0, 0.0), ang_vel_z=(0.5, 0.5)
            ),
        )

    env.close()
    cfg = AntEnvCfg()
    cfg.commands = Commands()
    env = ManagerBasedRLEnv(cfg)
    env.reset()
    set_root(env, lin_vel=(1.0, 0.0, 0.0), ang_vel=(0.0, 0.0, 0.5))
    torch.testing.assert_close(mdp.track_lin_vel_xy_exp(env, std=0.5, command_name="vel"), torch.ones(N))
    torch.testing.assert_close(mdp.track_ang_vel_z_exp(env, std=0.5, command_name="vel"), torch.ones(N))
    set_root(env, lin_vel=(0.0, 0.0, 0.0))
    torch.testing.assert_close(
        mdp.track_lin_vel_xy_exp(env, std=0.5, command_name="vel"), torch.full((N,), math.exp(-4.0))
    )
    env.close()


# -- terminations ----------------------------------------------------------------------------------


def test_terminations(env):
    flipped = (0.0, 1.0, 0.0, 0.0)  # 180 deg about x
    set_root(env, quat=flipped, height=0.1)
    assert mdp.bad_orientation(env, limit_angle=math.pi / 2).all()
    assert mdp.root_height_below_minimum(env, minimum_height=0.2).all()
    set_root(env)
    assert not mdp.bad_orientation(env, limit_angle=math.pi / 2).any()
    robot = env.scene["robot"]
    pos = robot.data.default_joint_pos.clone()
    vel = torch.zeros_like(pos)
    pos[0, 0] = 1.0  # hip beyond 40 deg
    vel[2, 3] = 9.0
    robot.write_joint_state_to_sim(pos, vel)
    assert mdp.joint_pos_out_of_limit(env).tolist() == [True, False, False, False]
    # Default ankles sit at +-0.785 rad, inside +-0.9; env 0's hip is at 1.0.
    out = mdp.joint_pos_out_of_manual_limit(env, bounds=(-0.9, 0.9), asset_cfg=resolved(env, ROBOT))
    assert out.tolist() == [True, False, False, False]
    assert mdp.joint_vel_out_of_manual_limit(env, max_velocity=5.0).tolist() == [False, False, True, False]
    env.episode_length_buf[:] = torch.tensor([0, env.max_episode_length, 3, env.max_episode_length + 1])
    assert mdp.time_out(env).tolist() == [False, True, False, True]


# -- contacts --------------------------------------------------------------------------------------


def test_contact_sensor_and_contact_terms(env):
    settle(env)
    box = env.scene["box_contact"]
    assert box.body_names == ["body"]
    force = box.data.net_forces_w[:, 0]
    torch.testing.assert_close(force[:, 2], torch.full((N,), BOX_MASS * 9.81), rtol=0.02, atol=0.0)
    assert force[:, :2].abs().max() < 0.1
    sensor = env.scene["robot_contacts"]
    feet, names = sensor.find_bodies(".*_foot")
    assert len(feet) == 4 and all(n.endswith("_foot") for n in names)
    assert sensor.data.net_forces_w_history.shape == (N, 3, sensor.num_bodies, 3)
    # The whole ant rests on the ground: the contact forces carry its weight.
    total = sensor.data.net_forces_w[..., 2].sum(1)
    weight = env.scene["robot"].data.default_mass[0].sum() * 9.81
    torch.testing.assert_close(total, torch.full((N,), float(weight)), rtol=0.05, atol=0.0)
    all_bodies = resolved(env, SceneEntityCfg("robot_contacts"))
    touching = mdp.undesired_contacts(env, threshold=1.0, sensor_cfg=all_bodies)
    assert (touching >= 1).all()
    assert mdp.illegal_contact(env, threshold=1.0, sensor_cfg=all_bodies).all()
    assert not mdp.illegal_contact(env, threshold=1e4, sensor_cfg=all_bodies).any()
    assert (mdp.contact_forces(env, threshold=0.0, sensor_cfg=all_bodies) >= total * 0.99).all()
    torso = resolved(env, SceneEntityCfg("robot_contacts", body_names=["front_left_leg"]))
    assert not mdp.illegal_contact(env, threshold=1.0, sensor_cfg=torso).any()  # hips stay in the air
    # Air time: lift the robot up; its feet leave the ground.
    air_before = sensor.data.current_air_time.clone()
    set_root(env, height=3.0)
    settle(env, 5)
    assert (sensor.data.current_air_time[:, feet] > air_before[:, feet]).all()
    assert sensor.compute_first_air(env.step_dt * 6).any()


def test_desired_contacts_penalizes_no_foot_on_the_ground(env):
    settle(env)
    sensor = env.scene["robot_contacts"]
    feet = resolved(env, SceneEntityCfg("robot_contacts", body_names=".*_foot"))
    assert sensor.num_bodies > len(feet.body_ids)
    torch.testing.assert_close(mdp.desired_contacts(env, sensor_cfg=feet), torch.zeros(N))  # standing
    set_root(env, height=3.0)
    settle(env, 5)  # in the air, longer than the sensor's history
    torch.testing.assert_close(mdp.desired_contacts(env, sensor_cfg=feet), torch.ones(N))


def test_command_resample_ends_the_episode_at_the_nth_command(env):
    @configclass
    class Commands:
        vel = mdp.UniformVelocityCommandCfg(
            asset_name="robot",
            resampling_time_range=(0.4, 0.4),
            ranges=mdp.UniformVelocityCommandCfg.Ranges(lin_vel_x=(1.0, 1.0), lin_vel_y=(0.0, 0.0), ang_vel_z=(0, 0)),
        )

    env.close()
    cfg = AntEnvCfg()
    cfg.commands = Commands()
    cfg.terminations.two_commands = DoneTerm(
        func=mdp.command_resample, params={"command_name": "vel", "num_resamples": 2}
    )
    env = ManagerBasedRLEnv(cfg)
    env.reset()
    steps_per_command = round(0.4 / env.step_dt)  # 20 env steps of 20 ms
    for step in range(1, 3 * steps_per_command):  # noqa: B007 - the count is checked
        _, _, terminated, _, _ = env.step(torch.zeros(N, 8))
        if terminated.any():
            break
    assert terminated.all() and step == 2 * steps_per_command  # as the second command runs out
    env.close()


# -- events ----------------------------------------------------------------------------------------


def test_reset_root_state_uniform_and_push(env):
    ids = torch.arange(N)
    pose_range = {"x": (-0.5, 0.5), "y": (0.2, 0.3), "yaw": (-math.pi, math.pi)}
    mdp.reset_root_state_uniform(env, ids, pose_range, {"z": (1.0, 2.0)}, asset_cfg=resolved(env, ROBOT))
    data = env.scene["robot"].data
    offset = data.root_pos_w - env.scene.env_origins - data.default_root_state[:, :3]
    assert (offset[:, 0].abs() <= 0.5).all() and ((offset[:, 1] >= 0.2) & (offset[:, 1] <= 0.3)).all()
    assert (data.root_lin_vel_w[:, 2] >= 1.0).all() and (data.root_lin_vel_w[:, 2] <= 2.0).all()
    assert data.heading_w.std() > 0.1
    before = data.root_lin_vel_w.clone()
    mdp.push_by_setting_velocity(env, torch.tensor([1]), {"x": (3.0, 3.0)}, asset_cfg=resolved(env, ROBOT))
    torch.testing.assert_close(data.root_lin_vel_w[1], before[1] + torch.tensor([3.0, 0.0, 0.0]))
    torch.testing.assert_close(data.root_lin_vel_w[[0, 2, 3]], before[[0, 2, 3]])


def test_reset_root_state_with_random_orientation(env):
    robot = env.scene["robot"]
    mdp.reset_root_state_with_random_orientation(
        env, torch.arange(N), {"z": (0.5, 0.5)}, {"yaw": (1.0, 1.0)}, asset_cfg=resolved(env, ROBOT)
    )
    data = robot.data
    offset = data.root_pos_w - env.scene.env_origins - data.default_root_state[:, :3]
    torch.testing.assert_close(offset, torch.tensor([[0.0, 0.0, 0.5]]).repeat(N, 1), atol=1e-6, rtol=0)
    torch.testing.assert_close(data.root_ang_vel_w[:, 2], torch.ones(N))
    up = math_utils.quat_apply(data.root_quat_w, torch.tensor([[0.0, 0.0, 1.0]]).repeat(N, 1))
    assert up[:, 2].std() > 0.1  # tilted every which way, not only turned about z
    with pytest.raises(ValueError, match=r"\['roll'\] are not used .*allowed: \['x', 'y', 'z'\]"):
        mdp.reset_root_state_with_random_orientation(env, torch.arange(N), {"roll": (0, 1)}, {})


def test_reset_joints_by_scale_and_offset(env):
    robot = env.scene["robot"]
    feet = resolved(env, SceneEntityCfg("robot", joint_names=[".*_foot"]))
    mdp.reset_joints_by_scale(env, torch.arange(N), (1.1, 1.2), (0.0, 0.0), asset_cfg=feet)
    ratio = robot.data.joint_pos[:, feet.joint_ids] / robot.data.default_joint_pos[:, feet.joint_ids]
    assert ((ratio >= 1.1 - 1e-6) & (ratio <= 1.2 + 1e-6)).all() and ratio.std() > 0
    # Scaled below the ankles' 30 deg limit, they are clamped to it.
    mdp.reset_joints_by_scale(env, torch.arange(N), (0.1, 0.2), (0.0, 0.0), asset_cfg=feet)
    low = robot.data.soft_joint_pos_limits[:, feet.joint_ids, 0]
    high = robot.data.soft_joint_pos_limits[:, feet.joint_ids, 1]
    pos = robot.data.joint_pos[:, feet.joint_ids]
    assert ((pos >= low - 1e-6) & (pos <= high + 1e-6)).all()
    torch.testing.assert_close(pos.abs(), torch.full_like(pos, 0.523599), atol=1e-5, rtol=0)
    mdp.reset_joints_by_offset(env, torch.tensor([0, 2]), (-0.1, 0.1), (0.5, 1.0), asset_cfg=resolved(env, ROBOT))
    vel = robot.data.joint_vel
    assert ((vel[[0, 2]] >= 0.5) & (vel[[0, 2]] <= 1.0)).all() and (vel[[1, 3]] == 0).all()


def test_randomize_mass_friction_gravity_gains_joint_parameters(env):
    ids = torch.arange(N)
    physics = env.sim.physics
    robot = env.scene["robot"]
    torso = resolved(env, SceneEntityCfg("robot", body_names=["torso"]))
    mdp.randomize_rigid_body_mass(env, ids, torso, (2.0, 3.0), operation="scale")
    ratio = robot.data.body_mass[:, 0] / robot.data.default_mass[:, 0]
    assert ((ratio >= 2.0) & (ratio <= 3.0)).all() and ratio.std() > 0
    torch.testing.assert_close(robot.data.body_mass[:, 1:], robot.data.default_mass[:, 1:])
    inertia = physics.model_field("body_inertia")[:, robot._body_ids[0]]
    torch.testing.assert_close(inertia, robot.data.default_inertia[:, 0] * ratio[:, None])

    from simlab.managers import EventTermCfg

    term_cfg = EventTermCfg(
        func=mdp.randomize_rigid_body_material, mode="startup", params={"asset_cfg": resolved(env, BOX)}
    )
    material = mdp.randomize_rigid_body_material(term_cfg, env)
    material(env, ids, (0.3, 0.4), (0.2, 0.3), (0.0, 0.0), num_buckets=16, asset_cfg=resolved(env, BOX))
    friction = physics.model_field("geom_friction")[:, env.sim.model.geom("Box/geom").id, 0]
    assert ((friction >= 0.3) & (friction <= 0.4)).all()

    mdp.randomize_physics_scene_gravity(env, torch.tensor([1]), ([0.0, 0.0, -5.0], [0.0, 0.0, -5.0]), operation="abs")
    torch.testing.assert_close(physics.model_field("opt.gravity")[1], torch.tensor([0.0, 0.0, -5.0]))
    torch.testing.assert_close(physics.model_field("opt.gravity")[0], torch.tensor([0.0, 0.0, -9.81]))
    # The box in the low-gravity world pushes on the ground with m * 5.
    settle(env, 20)
    box_force = env.scene["box_contact"].data.net_forces_w[:, 0, 2]
    assert box_force[1] == pytest.approx(BOX_MASS * 5.0, rel=0.02) and box_force[0] == pytest.approx(
        BOX_MASS * 9.81, rel=0.02
    )

    legs = resolved(env, SceneEntityCfg("robot", joint_names=[".*_leg"]))
    mdp.randomize_actuator_gains(
        env, ids, legs, stiffness_distribution_params=(10.0, 20.0), damping_distribution_params=(1.0, 1.0)
    )
    kp = robot.data.joint_stiffness
    assert ((kp[:, legs.joint_ids] >= 10.0) & (kp[:, legs.joint_ids] <= 20.0)).all()
    hip_ids = legs.joint_ids
    feet_ids = [j for j in range(8) if j not in hip_ids]
    assert (kp[:, feet_ids] == 0).all()
    torch.testing.assert_close(robot.data.joint_damping[:, hip_ids], torch.ones(N, 4))

    term_cfg = EventTermCfg(func=mdp.randomize_joint_parameters, mode="startup", params={"asset_cfg": legs})
    joint_params = mdp.randomize_joint_parameters(term_cfg, env)
    joint_params(
        env,
        ids,
        legs,
        friction_distribution_params=(0.5, 0.6),
        armature_distribution_params=(2.0, 2.0),
        operation="abs",
    )
    assert (
        (robot.data.joint_friction_coeff[:, hip_ids] >= 0.5) & (robot.data.joint_friction_coeff[:, hip_ids] <= 0.6)
    ).all()
    dof_armature = physics.model_field("dof_armature")
    assert torch.allclose(dof_armature[:, robot._dof_index[hip_ids]], torch.full((N, 4), 2.0))


def test_reset_events_that_read_the_host_are_named_as_graph_blockers():
    """A mask-taking event that still calls MuJoCo's set_const (a host read) declares itself, so the
    step goes eager for that reason rather than through a failed capture; the others stay graphable."""
    from simlab.managers import EventTermCfg

    legs = SceneEntityCfg("robot", joint_names=[".*_leg"])
    events = {
        "robot_mass": (mdp.randomize_rigid_body_mass, {"asset_cfg": SceneEntityCfg("robot", body_names=["torso"])}),
        "box_mass": (mdp.randomize_rigid_body_mass, {"asset_cfg": BOX}),
        "armature": (mdp.randomize_joint_parameters, {"asset_cfg": legs, "armature_distribution_params": (0.1, 0.2)}),
        "friction": (mdp.randomize_joint_parameters, {"asset_cfg": legs, "friction_distribution_params": (0.1, 0.2)}),
    }
    cfg = AntEnvCfg()
    for name, (func, params) in events.items():
        params = {"mass_distribution_params": (0.8, 1.2), "operation": "scale", **params}
        if func is mdp.randomize_joint_parameters:
            params.pop("mass_distribution_params")
        setattr(cfg.events, name, EventTermCfg(func=func, mode="reset", params=params))
    env = ManagerBasedRLEnv(cfg)
    try:
        blockers = env.event_manager.graph_blockers()
        assert len(blockers) == 2, blockers
        robot_mass, armature = blockers
        assert robot_mass.startswith("event term 'robot_mass' (mode 'reset') randomizes the masses of articulated")
        assert "set_const" in robot_mass and "host read" in robot_mass
        assert armature.startswith("event term 'armature' (mode 'reset') randomizes joint armature")
        assert env.graph_blockers() == blockers
        env.reset()
        env.step(torch.zeros(N, 8))  # the terms still run by mask (eagerly on the CPU)
    finally:
        env.close()


def test_external_force_lifts_the_box(env):
    box = env.scene["box"]
    mdp.apply_external_force_torque(
        env, torch.tensor([2]), (BOX_MASS * 9.81 * 2, BOX_MASS * 9.81 * 2), (0.0, 0.0), asset_cfg=resolved(env, BOX)
    )
    settle(env, 10)
    heights = box.data.root_pos_w[:, 2]
    assert heights[2] > 0.3 and (heights[[0, 1, 3]] < 0.15).all()
