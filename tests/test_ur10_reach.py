"""The UR10 arm and its reach task: Isaac Lab's joint names, forward kinematics equal to Universal
Robots' published DH parameters, the task builds and steps, a scripted differential-IK controller
brings ``ee_link`` to a fixed target, and the task names its success criterion."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import gymnasium as gym
import mujoco
import numpy as np
import torch
from conftest import load_script

import simlab.sim as sim_utils
import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.controllers import DifferentialIKController, DifferentialIKControllerCfg
from simlab.envs import ManagerBasedRLEnv
from simlab.robots.universal_robots import UR10_CFG
from simlab.tasks.manager_based.manipulation.reach.config.ur_10.joint_pos_env_cfg import (
    UR10ReachEnvCfg,
    UR10ReachEnvCfg_PLAY,
)
from simlab.tasks.utils.criteria import criterion_for
from simlab.utils.math import quat_error_magnitude, quat_from_euler_xyz, quat_slerp, subtract_frame_transforms

PORTED = Path(__file__).parent / "ported" / "isaaclab_reach_ur10_joint_pos_env_cfg.py"
JOINTS = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"]
# UR10 (CB3) standard DH parameters, as Universal Robots publishes them
DH_D = [0.1273, 0.0, 0.0, 0.163941, 0.1157, 0.0922]
DH_A = [0.0, -0.612, -0.5723, 0.0, 0.0, 0.0]
DH_ALPHA = [math.pi / 2, 0.0, 0.0, math.pi / 2, -math.pi / 2, 0.0]


def dh_tool_pose(q: np.ndarray) -> np.ndarray:
    pose = np.eye(4)
    for theta, d, a, alpha in zip(q, DH_D, DH_A, DH_ALPHA, strict=True):
        ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
        pose = pose @ np.array(
            [[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st], [0, sa, ca, d], [0, 0, 0, 1]]
        )
    return pose


def make_env(num_envs: int = 2, gravity: bool = True) -> ManagerBasedRLEnv:
    cfg = UR10ReachEnvCfg()
    cfg.scene.num_envs = num_envs
    if not gravity:  # as Isaac Lab's task-space (IK) configs run their arms
        cfg.scene.robot.spawn.rigid_props = sim_utils.RigidBodyPropertiesCfg(disable_gravity=True)
    cfg.sim.device = "cpu"
    cfg.seed = 0
    return ManagerBasedRLEnv(cfg)


def test_the_model_has_isaac_labs_joint_names_and_the_published_dh_kinematics():
    model = mujoco.MjModel.from_xml_path(UR10_CFG.spawn.asset_path)
    data = mujoco.MjData(model)
    assert [model.joint(i).name for i in range(model.njnt)] == JOINTS
    assert set(UR10_CFG.init_state.joint_pos) == set(JOINTS)
    # ROS's base_link is the DH base frame turned half a turn about z; ee_link's x axis is the DH tool z axis
    base_turn = np.diag([-1.0, -1.0, 1.0])
    ee = model.body("ee_link").id
    for q in np.random.default_rng(0).uniform(-2.5, 2.5, size=(5, 6)):
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        tool = dh_tool_pose(q)
        np.testing.assert_allclose(data.xpos[ee], base_turn @ tool[:3, 3], atol=1e-6)
        np.testing.assert_allclose(data.xmat[ee].reshape(3, 3)[:, 0], base_turn @ tool[:3, 2], atol=1e-6)


def test_reach_tasks_build_and_step():
    for task in ("simlab/Reach-UR10-v0", "simlab/Reach-UR10-Play-v0"):
        env = gym.make(task, cfg=_cpu_cfg(task))
        obs, _ = env.reset(seed=0)
        robot = env.unwrapped.scene["robot"]
        assert robot.joint_names == JOINTS
        assert env.action_space.shape == (2, 6)
        for _ in range(3):
            obs, reward, terminated, truncated, _ = env.step(torch.zeros(env.action_space.shape))
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
        env.close()


def _cpu_cfg(task: str):
    from simlab.tasks.utils.parse_cfg import parse_env_cfg

    return parse_env_cfg(task, device="cpu", num_envs=2)


def test_scripted_differential_ik_brings_the_end_effector_to_a_fixed_target():
    """A target in the reach command's range, tool pointing down as the task commands it, approached
    along a straight line over one second (one IK step from the start pose would cross the wrist
    singularity of the default pose, wrist_2 at 0). Gravity is off on the arm, as in Isaac Lab's IK
    configs: with it, the PD's steady sag stays as an error of the measured-pose IK."""
    env = make_env(gravity=False)
    env.reset()
    robot = env.scene["robot"]
    ee = robot.find_bodies("ee_link")[0][0]
    ik = DifferentialIKController(
        DifferentialIKControllerCfg(command_type="pose", ik_method="dls"), env.num_envs, "cpu"
    )
    target_pos = torch.tensor([[0.55, 0.1, 0.3]]).repeat(env.num_envs, 1)
    down = torch.tensor(math.pi / 2)
    target_quat = quat_from_euler_xyz(torch.zeros(1), down.reshape(1), torch.zeros(1)).repeat(env.num_envs, 1)
    scale, offset = 0.5, robot.data.default_joint_pos

    def ee_pose():
        return subtract_frame_transforms(
            robot.data.root_pos_w, robot.data.root_quat_w, robot.data.body_pos_w[:, ee], robot.data.body_quat_w[:, ee]
        )

    start_pos, start_quat = ee_pose()
    for step in range(90):
        along = min(1.0, (step + 1) / 30)
        quat_along = torch.stack([quat_slerp(q0, q1, along) for q0, q1 in zip(start_quat, target_quat)])
        ik.set_command(torch.cat([start_pos + along * (target_pos - start_pos), quat_along], dim=-1))
        pos, quat = ee_pose()
        jacobian = robot.root_physx_view.get_jacobians()[:, ee - 1, :, :]
        env.step((ik.compute(pos, quat, jacobian, robot.data.joint_pos) - offset) / scale)
    pos, quat = ee_pose()
    assert (pos - target_pos).norm(dim=-1).max() < 1e-3
    assert quat_error_magnitude(quat, target_quat).max() < 1e-2


def test_reach_tasks_register_the_reach_criterion():
    for task in ("simlab/Reach-UR10-v0", "simlab/Reach-UR10-Play-v0"):
        criterion = criterion_for(task)
        assert "mean position error < 0.02 m" in criterion.description


def test_isaac_labs_ur10_reach_config_runs_after_the_import_mapping():
    """``tests/ported/isaaclab_reach_ur10_joint_pos_env_cfg.py`` is Isaac Lab's file with its imports
    mapped: it configures the same task as simlab's own and builds and steps."""
    ported = load_script(PORTED, "isaaclab_reach_ur10_joint_pos_env_cfg")
    try:
        for theirs, ours in (
            (ported.UR10ReachEnvCfg, UR10ReachEnvCfg),
            (ported.UR10ReachEnvCfg_PLAY, UR10ReachEnvCfg_PLAY),
        ):
            assert theirs().to_dict() == ours().to_dict()
        cfg = ported.UR10ReachEnvCfg()
        cfg.scene.num_envs, cfg.sim.device, cfg.seed = 2, "cpu", 0
        env = ManagerBasedRLEnv(cfg)
        env.reset()
        obs, reward, *_ = env.step(torch.zeros(2, 6))
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
        env.close()
    finally:
        sys.modules.pop("isaaclab_reach_ur10_joint_pos_env_cfg", None)


def test_the_registered_agent_normalizes_observations_and_random_actions_miss_the_criterion():
    """The task registers Isaac Lab's agent with normalized observations and [256, 128, 64] networks,
    as the Franka reach tasks that learned; the criterion can fail: random actions score far above 1."""
    from simlab.tasks.utils.parse_cfg import load_cfg_from_registry

    agent = load_cfg_from_registry("simlab/Reach-UR10-v0", "rsl_rl_cfg_entry_point")
    assert agent.actor.obs_normalization and agent.critic.obs_normalization
    assert agent.actor.hidden_dims == [256, 128, 64] and agent.algorithm.entropy_coef == 0.01  # UR10's own
    criterion = criterion_for("simlab/Reach-UR10-v0")
    env = make_env(num_envs=16)
    env.reset()
    on_step, errors = criterion.make_hook()
    torch.manual_seed(0)
    for _ in range(int(criterion.play_seconds(0.0) / env.step_dt)):
        actions = torch.randn(env.num_envs, 6)
        obs, *_ = env.step(actions)
        on_step(env, obs, actions)
    score, passed = criterion.judge({}, errors)
    assert not passed and score > 10.0
    env.close()
