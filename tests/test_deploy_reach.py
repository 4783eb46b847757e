"""The deployed reach tasks (Isaac Lab's ``Isaac-Deploy-Reach-UR10e-v0`` and ``-Rizon4s-v0``) and their arms:
Isaac Lab's joint names, forward kinematics equal to the makers' published kinematics, the keypoint
rewards against hand-computed values, the tasks build and step on both backends, and the criterion
reads the pose in the "base" frame the tasks track commands in."""

from __future__ import annotations

import math
from types import SimpleNamespace

import gymnasium as gym
import mujoco
import numpy as np
import pytest
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.envs import ManagerBasedRLEnv
from simlab.managers import SceneEntityCfg
from simlab.robots import FLEXIV_RIZON4S_CFG, UR10e_CFG
from simlab.tasks.manager_based.manipulation.deploy import mdp
from simlab.tasks.utils.criteria import criterion_for
from simlab.tasks.utils.parse_cfg import load_cfg_from_registry, parse_env_cfg
from simlab.utils.math import quat_from_euler_xyz

TASK = "simlab/Deploy-Reach-UR10e-v0"
RIZON = "simlab/Deploy-Reach-Rizon4s-v0"
TASKS = [
    f"simlab/Deploy-Reach-{arm}{suffix}"
    for arm in ("UR10e", "Rizon4s")
    for suffix in ("-v0", "-Play-v0", "-ROS-Inference-v0")
]
JOINTS = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"]
RIZON_JOINTS = [f"joint{i}" for i in range(1, 8)]
# Flexiv's Rizon 4s description: each joint's origin (xyz, rpy) in its parent link and its axis; the flange
RIZON_CHAIN = [
    ((0.0, 0.0, 0.155), (0.0, 0.0, math.pi), (0, 0, 1)),
    ((0.0, 0.03, 0.21), (0.0, 0.0, 0.0), (0, 1, 0)),
    ((0.0, 0.035, 0.205), (0.0, 0.0, 0.0), (0, 0, 1)),
    ((-0.02, -0.03, 0.19), (0.0, 0.0, -math.pi), (0, 1, 0)),
    ((-0.02, 0.025, 0.195), (0.0, 0.0, -math.pi), (0, 0, 1)),
    ((0.0, 0.03, 0.19), (0.0, 0.0, 0.0), (0, 1, 0)),
    ((-0.055, 0.07, 0.11), (0.0, -math.pi / 2, 0.0), (0, 0, 1)),
]
RIZON_FLANGE = ((0.0, 0.0, 0.124), (0.0, 0.0, -math.pi))
# UR10e standard DH parameters, as Universal Robots publishes them
DH_D = [0.1807, 0.0, 0.0, 0.17415, 0.11985, 0.11655]
DH_A = [0.0, -0.6127, -0.57155, 0.0, 0.0, 0.0]
DH_ALPHA = [math.pi / 2, 0.0, 0.0, math.pi / 2, -math.pi / 2, 0.0]


def dh_flange_pose(q: np.ndarray) -> np.ndarray:
    pose = np.eye(4)
    for theta, d, a, alpha in zip(q, DH_D, DH_A, DH_ALPHA, strict=True):
        ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
        pose = pose @ np.array(
            [[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st], [0, sa, ca, d], [0, 0, 0, 1]]
        )
    return pose


def _rotation(axis: tuple[float, float, float], angle: float) -> np.ndarray:
    x, y, z = axis
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def _urdf_origin(xyz, rpy) -> np.ndarray:
    pose = np.eye(4)
    roll, pitch, yaw = rpy
    pose[:3, :3] = _rotation((0, 0, 1), yaw) @ _rotation((0, 1, 0), pitch) @ _rotation((1, 0, 0), roll)
    pose[:3, 3] = xyz
    return pose


def rizon_flange_pose(q: np.ndarray) -> np.ndarray:
    pose = np.eye(4)
    for (xyz, rpy, axis), angle in zip(RIZON_CHAIN, q, strict=True):
        turn = np.eye(4)
        turn[:3, :3] = _rotation(axis, angle)
        pose = pose @ _urdf_origin(xyz, rpy) @ turn
    return pose @ _urdf_origin(*RIZON_FLANGE)


def make_env(num_envs: int = 4, engine: str = "mujoco", task: str = TASK) -> ManagerBasedRLEnv:
    cfg = parse_env_cfg(task, device="cpu", num_envs=num_envs)
    cfg.sim.engine, cfg.sim.use_cuda_graph, cfg.seed = engine, False, 0
    return ManagerBasedRLEnv(cfg)


def test_the_model_has_isaac_labs_joint_names_the_published_masses_and_dh_kinematics():
    model = mujoco.MjModel.from_xml_path(UR10e_CFG.spawn.asset_path)
    data = mujoco.MjData(model)
    assert [model.joint(i).name for i in range(model.njnt)] == JOINTS
    assert set(UR10e_CFG.init_state.joint_pos) == set(JOINTS)
    assert model.body_mass.sum() == pytest.approx(4.0 + 7.369 + 13.051 + 3.989 + 2.1 + 1.98 + 0.615)
    # base_link is the DH base frame ("base") turned half a turn about z; wrist_3_link is the DH flange frame
    base_turn = np.diag([-1.0, -1.0, 1.0])
    flange = model.body("wrist_3_link").id
    for q in np.random.default_rng(0).uniform(-2.5, 2.5, size=(5, 6)):
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        pose = dh_flange_pose(q)
        np.testing.assert_allclose(data.xpos[flange], base_turn @ pose[:3, 3], atol=1e-9)
        np.testing.assert_allclose(data.xmat[flange].reshape(3, 3), base_turn @ pose[:3, :3], atol=1e-9)


def test_the_rizon_model_has_isaac_labs_joint_names_flexivs_masses_and_kinematics():
    model = mujoco.MjModel.from_xml_path(FLEXIV_RIZON4S_CFG.spawn.asset_path)
    data = mujoco.MjData(model)
    assert [model.joint(i).name for i in range(model.njnt)] == RIZON_JOINTS
    assert set(FLEXIV_RIZON4S_CFG.init_state.joint_pos) == set(RIZON_JOINTS)
    assert model.body_mass.sum() == pytest.approx(3.7 + 3.7 + 2.7 + 3 * 2.4 + 2.1 + 1.4)
    flange = model.body("flange").id
    for q in np.random.default_rng(0).uniform(-1.3, 1.3, size=(5, 7)):
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        pose = rizon_flange_pose(q)
        np.testing.assert_allclose(data.xpos[flange], pose[:3, 3], atol=1e-9)
        np.testing.assert_allclose(data.xmat[flange].reshape(3, 3), pose[:3, :3], atol=1e-7)


def test_keypoint_distances_and_reward_match_hand_computed_values():
    pos = torch.zeros(2, 3)
    quat = torch.tensor([[1.0, 0.0, 0.0, 0.0]]).repeat(2, 1)
    # a shift moves every keypoint by it; a turn about z by theta moves the 4 keypoints on x and y by
    # 2 s sin(theta / 2) and leaves the centre and the 2 on z
    target_pos = torch.tensor([[0.03, 0.0, 0.04], [0.0, 0.0, 0.0]])
    theta = 0.3
    target_quat = torch.stack([quat[0], quat_from_euler_xyz(torch.zeros(1), torch.zeros(1), torch.tensor([theta]))[0]])
    distance = mdp.compute_keypoint_distance(pos, quat, target_pos, target_quat, keypoint_scale=0.45)
    assert distance.shape == (2, 7)
    torch.testing.assert_close(distance[0], torch.full((7,), 0.05))
    moved = 2 * 0.45 * math.sin(theta / 2)
    torch.testing.assert_close(distance[1].sort().values, torch.tensor([0.0, 0.0, 0.0, moved, moved, moved, moved]))
    # the reward terms read the frame transformer's first target and the command: the mean distance d,
    # and the bonus sum over (a, b) of 1 / (exp(a d) + b + exp(-a d))
    frame = SimpleNamespace(data=SimpleNamespace(target_pos_source=pos[:, None], target_quat_source=quat[:, None]))
    command = torch.cat([target_pos, target_quat], dim=-1)
    env = SimpleNamespace(scene={"ee": frame}, command_manager=SimpleNamespace(get_command=lambda name: command))
    ee, coeffs = SceneEntityCfg("ee"), [(50, 1e-4), (300, 1e-4)]
    d = 4 * moved / 7
    error = mdp.keypoint_command_error(env, "ee_pose", ee, keypoint_scale=0.45)
    torch.testing.assert_close(error, torch.tensor([0.05, d]))
    bonus = mdp.keypoint_command_error_exp(env, "ee_pose", ee, coeffs, kp_use_sum_of_exps=False, keypoint_scale=0.45)
    expected = [sum(1 / (math.exp(a * x) + b + math.exp(-a * x)) for a, b in coeffs) for x in (0.05, d)]
    torch.testing.assert_close(bonus, torch.tensor(expected))


@pytest.mark.parametrize("task", TASKS)
def test_tasks_build_and_step_with_isaac_labs_spaces(task):
    joints = RIZON_JOINTS if "Rizon" in task else JOINTS
    n = len(joints)
    env = gym.make(task, cfg=parse_env_cfg(task, device="cpu", num_envs=2))
    try:
        obs, _ = env.reset(seed=0)
        assert env.unwrapped.scene["robot"].joint_names == joints
        # the ROS node's observation and action sizes: joint positions and velocities, a pose
        assert obs["policy"].shape == (2, 2 * n + 7) and env.action_space.shape == (2, n)
        for _ in range(3):
            obs, reward, *_ = env.step(torch.randn(env.action_space.shape))
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
        if "ROS" in task:
            cfg = env.unwrapped.cfg
            assert cfg.obs_order == ["arm_dof_pos", "arm_dof_vel", "target_pos", "target_quat"]
            assert cfg.action_scale_joint_space == [0.0625] * n and cfg.arm_joint_names == joints
            assert cfg.observation_space == 2 * n + 7 and cfg.action_space == n
    finally:
        env.close()


@pytest.mark.parametrize("task", [TASK, RIZON])
@pytest.mark.parametrize("engine", ["mujoco", "mujoco_warp"])
def test_the_task_steps_on_both_backends_and_actions_move_the_targets_by_a_sixteenth(engine, task):
    """Relative joint-position actions: each physics step, the drive's target is the joint's position
    then plus 0.0625 x the action; random actions keep the arm finite and slow (no torque cap: Isaac
    Lab's UR10e config has none; the Rizon 4s is capped, with simlab's armature)."""
    if engine == "mujoco_warp":
        pytest.importorskip("mujoco_warp")
    env = make_env(engine=engine, task=task)
    try:
        env.reset()
        robot, term = env.scene["robot"], env.action_manager.get_term("arm_action")
        torch.manual_seed(0)
        for _ in range(30):
            actions = torch.randn(env.num_envs, robot.num_joints)
            obs, reward, *_ = env.step(actions)
            torch.testing.assert_close(term.processed_actions, 0.0625 * actions)
            # the last physics step's target: the position after the first one (at most one physics step
            # at the speed bound below from where the joints end), plus the same offset
            moved = robot.data.joint_pos_target - term.processed_actions - robot.data.joint_pos
            assert moved.abs().max() < 10.0 * env.physics_dt
            assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
            assert robot.data.joint_vel.abs().max() < 10.0
    finally:
        env.close()


def test_criterion_reads_the_flange_in_the_base_frame_and_random_actions_miss_it():
    """Commanding the flange's own pose in the "base" frame (base_link turned half a turn) scores ~0;
    the same pose read in base_link's frame would be off by twice the flange's horizontal distance from
    the base. Random actions score far above 1."""
    criterion = criterion_for(TASK)
    assert "mean position error < 0.02 m" in criterion.description
    env = make_env(num_envs=8)
    try:
        env.reset()
        frame = env.scene["ee_frame_wrt_base_frame"].data
        term = env.command_manager.get_term("ee_pose")
        on_step, errors = criterion.make_hook()
        zero = torch.zeros(env.num_envs, 6)
        for _ in range(int(4.0 / env.step_dt) + 1):
            term.pose_command_b[:] = torch.cat([frame.target_pos_source[:, 0], frame.target_quat_source[:, 0]], -1)
            obs, *_ = env.step(zero)
            on_step(env, obs, zero)
        score, passed = criterion.judge({}, errors)
        assert passed and score < 0.05
        assert frame.target_pos_source[:, 0, :2].norm(dim=-1).min() > 0.5  # base_link's frame would be far off

        env.reset()
        on_step, errors = criterion.make_hook()
        torch.manual_seed(0)
        for _ in range(int(criterion.play_seconds(0.0) / env.step_dt)):
            actions = torch.randn(env.num_envs, 6)
            obs, *_ = env.step(actions)
            on_step(env, obs, actions)
        score, passed = criterion.judge({}, errors)
        assert not passed and score > 5.0
    finally:
        env.close()


@pytest.mark.parametrize(("task", "experiment"), [(TASK, "reach_ur10e"), (RIZON, "reach_rizon4s")])
def test_the_registered_agent_is_isaac_labs(task, experiment):
    agent = load_cfg_from_registry(task, "rsl_rl_cfg_entry_point")
    assert agent.num_steps_per_env == 512 and agent.experiment_name == experiment
    assert agent.actor.obs_normalization and agent.actor.hidden_dims == [256, 128, 64]
    assert agent.algorithm.learning_rate == 5.0e-4 and agent.algorithm.desired_kl == 0.008
    assert "mean position error < 0.02 m" in criterion_for(task).description
