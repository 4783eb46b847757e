"""The direct Franka cabinet task: the cabinet model, spaces, reward terms of hand-set states,
resets by mask, and a scripted grasp that pulls the drawer open (on MuJoCo and on MuJoCo Warp's CPU device)."""

from __future__ import annotations

import gymnasium as gym
import pytest
import torch
from test_engine_choice import needs_warp

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.controllers import DifferentialIKController, DifferentialIKControllerCfg
from simlab.tasks.direct.franka_cabinet.franka_cabinet_env import (
    DRAWER_OPENING_OBS,
    REWARD_TERMS,
    FrankaCabinetEnv,
    compute_rewards,
)
from simlab.tasks.utils import parse_env_cfg
from simlab.utils.math import quat_apply, quat_from_matrix

TASK = "simlab/Franka-Cabinet-Direct-v0"
SCALES = dict(dist_reward_scale=1.5, rot_reward_scale=1.5, open_reward_scale=10.0, action_penalty_scale=0.05,
              finger_reward_scale=2.0)  # fmt: skip


def make(num_envs: int = 2, engine: str = "auto") -> FrankaCabinetEnv:
    cfg = parse_env_cfg(TASK, device="cpu", num_envs=num_envs)
    cfg.sim.engine = engine
    cfg.seed = 0
    env = gym.make(TASK, cfg=cfg).unwrapped
    env.reset(seed=0)
    return env


@pytest.fixture(scope="module")
def env():
    env = make()
    yield env
    env.close()


def test_spaces_names_and_spawn_pose(env):
    obs, *_ = env.step(torch.zeros(2, 9))
    assert obs["policy"].shape == (2, 23) and env.single_action_space.shape == (9,)
    assert env.graph_blockers() == []  # resets by mask: the step can replay as a CUDA graph
    assert set(env._cabinet.joint_names) == {"drawer_top_joint", "drawer_bottom_joint", "door_left_joint",
                                             "door_right_joint"}  # fmt: skip
    assert {"sektion", "drawer_top", "drawer_handle_top"} <= set(env._cabinet.body_names)
    # the drawer's grip point is the handle bar's centre, 71 cm up, 30 cm in front of the cabinet's origin
    expected = env.scene.env_origins + torch.tensor([0.3, 0.01, 0.71])
    torch.testing.assert_close(env.drawer_grasp_pos, expected, atol=1e-4, rtol=0)
    # Isaac Lab's robot grasp frame: the fingers' midpoint in panda_link7's frame, plus 4 cm along its y
    torch.testing.assert_close(env.robot_local_grasp_pos[0], torch.tensor([0.0, 0.04, 0.1654]), atol=1e-4, rtol=0)
    # observation layout: ..., grasp point to handle (18:21), drawer opening, drawer speed
    torch.testing.assert_close(obs["policy"][:, 18:21], env.drawer_grasp_pos - env.robot_grasp_pos)
    assert obs["policy"][:, 21].abs().max() < 1e-3


def test_reward_terms_of_hand_set_states():
    n = 2
    up, forward = torch.tensor([0.0, 1.0, 0.0]).repeat(n, 1), torch.tensor([0.0, 0.0, 1.0]).repeat(n, 1)
    inward, drawer_up = torch.tensor([-1.0, 0.0, 0.0]).repeat(n, 1), torch.tensor([0.0, 0.0, 1.0]).repeat(n, 1)
    # env 0: grasp point on the handle, gripper aligned (its z into the drawer, its y up), drawer 25 cm
    # open, fingers above / below the handle, no action. env 1: 10 cm away, gripper turned 180 degrees
    # about the drawer's up axis (anti-aligned forward, aligned up), drawer shut, left finger 1 cm too
    # low, action 0.5 on every joint.
    aligned = quat_from_matrix(torch.tensor([[0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]))
    turned = quat_from_matrix(torch.tensor([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]))
    handle = torch.tensor([[0.3, 0.0, 0.7], [0.3, 0.0, 0.7]])
    rewards, terms = compute_rewards(
        actions=torch.tensor([[0.0] * 9, [0.5] * 9]),
        drawer_opening=torch.tensor([0.25, 0.0]),
        franka_grasp_pos=handle + torch.tensor([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0]]),
        drawer_grasp_pos=handle,
        franka_grasp_rot=torch.stack([aligned, turned]),
        drawer_grasp_rot=torch.tensor([[1.0, 0.0, 0.0, 0.0]] * 2),
        franka_lfinger_pos=torch.tensor([[0.3, 0.0, 0.72], [0.4, 0.0, 0.69]]),
        franka_rfinger_pos=torch.tensor([[0.3, 0.0, 0.68], [0.4, 0.0, 0.68]]),
        gripper_forward_axis=forward,
        drawer_inward_axis=inward,
        gripper_up_axis=up,
        drawer_up_axis=drawer_up,
        **SCALES,
    )
    assert tuple(terms) == REWARD_TERMS
    expected = {
        "dist_reward": [1.5 * 2.0, 1.5 / 1.01**2],  # (1 / (1 + d^2))^2, doubled within 2 cm
        "rot_reward": [1.5 * 1.0, 1.5 * 0.5 * (-1.0 + 1.0)],  # signed squares of the two axis dots
        "open_reward": [2.5, 0.0],
        "action_penalty": [0.0, -0.05 * 9 * 0.25],
        "finger_dist_penalty": [0.0, 2.0 * -0.01],  # only the finger on the wrong side counts
    }
    for name, values in expected.items():
        torch.testing.assert_close(terms[name], torch.tensor(values), atol=1e-5, rtol=0, msg=name)
    bonus = torch.tensor([0.25 + 0.25, 0.0])  # past 1 cm and past 20 cm
    total = sum(torch.tensor(v) for v in expected.values()) + bonus
    torch.testing.assert_close(rewards, total, atol=1e-5, rtol=0)


def test_open_drawer_terminates_and_reset_by_mask_touches_only_that_env(env):
    for _ in range(5):
        env.step(torch.rand(2, 9) * 2 - 1)
    joint_pos = env._cabinet.data.joint_pos.clone()
    joint_pos[0, env.drawer_joint_idx] = 0.395  # past the 39 cm that ends an episode
    env._cabinet.write_joint_state_to_sim(joint_pos, torch.zeros_like(joint_pos))
    robot_before = env._robot.data.joint_pos.clone()
    _, _, terminated, truncated, extras = env.step(torch.zeros(2, 9))
    assert terminated.tolist() == [True, False] and not truncated.any()
    assert extras["final_obs"]["policy"][0, DRAWER_OPENING_OBS] > 0.38  # the finished episode's last observation
    # env 0 starts again: drawer shut, arm within the reset noise of its default pose, targets there too
    assert env._cabinet.data.joint_pos[0].abs().max() < 1e-6
    offset = env._robot.data.joint_pos[0] - env._robot.data.default_joint_pos[0]
    assert offset.abs().max() <= env.cfg.reset_joint_noise + 1e-5
    torch.testing.assert_close(env.robot_dof_targets[0], env._robot.data.joint_pos[0])
    assert (env._robot.data.joint_pos[1] - robot_before[1]).abs().max() < 0.05  # env 1 went on
    assert set(REWARD_TERMS) <= set(extras["log"])


def open_drawer_by_script(env: FrankaCabinetEnv, steps: int = 440) -> torch.Tensor:
    """Grasp the top drawer's handle and pull, through the task's own actions; returns the openings.

    Differential IK (world frame) gives the arm's joint targets for a hand pose in front of the handle,
    then on it; the fingers close; the target then moves out 35 cm. The actions move the joint targets
    to the IK's joint positions plus the gravity sag of the arm's PD drives (g(q) / kp) minus a little
    damping, so the soft drives track the pose.
    """
    n, robot = env.num_envs, env._robot
    hand = robot.find_bodies("panda_hand")[0][0]
    arm = robot.find_joints("panda_joint[1-7]")[0]
    kp = env.cfg.robot.actuators["panda_shoulder"].stiffness
    ik_cfg = DifferentialIKControllerCfg(command_type="pose", use_relative_mode=False, ik_method="dls")
    ik = DifferentialIKController(ik_cfg, n, env.device)
    # the hand's z axis into the cabinet (-x), its fingers opening up and down (y = world z)
    hand_quat = quat_from_matrix(torch.tensor([[0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])).repeat(n, 1)
    fingertip_centre = torch.tensor([0.0, 0.0, 0.1034]).repeat(n, 1)
    handle = env.drawer_grasp_pos.clone()
    per_step = 1.0 / (env.dt * env.cfg.action_scale)
    openings = []
    for k in range(steps):
        close = k >= 190
        stand_off = 0.12 if k < 100 else min(0.35, max(0.0, (k - 220) * 0.003))  # in front of the handle [m]
        tcp_target = handle + torch.tensor([stand_off, 0.0, 0.0])
        ik.set_command(torch.cat([tcp_target - quat_apply(hand_quat, fingertip_centre), hand_quat], dim=-1))
        jacobian = robot.root_physx_view.get_jacobians()[:, hand - 1][:, :, arm]
        joint_pos = robot.data.joint_pos[:, arm]
        q_des = ik.compute(robot.data.body_pos_w[:, hand], robot.data.body_quat_w[:, hand], jacobian, joint_pos)
        sag = robot.root_physx_view.get_gravity_compensation_forces()[:, arm] / kp
        targets = q_des + sag - 0.1 * robot.data.joint_vel[:, arm]
        actions = torch.full((n, 9), -1.0 if close else 1.0)
        actions[:, :7] = ((targets - env.robot_dof_targets[:, :7]) * per_step).clamp(-1.0, 1.0)
        env.step(actions)
        openings.append(env._cabinet.data.joint_pos[:, env.drawer_joint_idx].clone())
    return torch.stack(openings)


def test_scripted_grasp_pulls_the_drawer_open():
    env = make(num_envs=2)
    try:
        openings = open_drawer_by_script(env)
    finally:
        env.close()
    assert openings[150].abs().max() < 0.01  # reaching the handle did not push or pull it
    assert (openings[-1] > 0.3).all(), openings[-1]  # held while pulled out 35 cm
    assert (openings.max(dim=0).values < 0.39).all()  # no episode ended on the way


@needs_warp
def test_mujoco_warp_on_cpu_steps_the_cabinet_like_mujoco():
    """The GPU backend (on Warp's CPU device) and MuJoCo C give the same first steps."""
    trajectories = []
    for engine in ("mujoco", "mujoco_warp"):
        env = make(num_envs=2, engine=engine)
        actions = torch.Generator().manual_seed(0)
        frames = []
        for _ in range(15):
            obs, *_ = env.step(torch.rand(2, 9, generator=actions) * 2 - 1)
            frames.append(obs["policy"])
        env.close()
        trajectories.append(torch.stack(frames))
    assert (trajectories[0][-1] - trajectories[0][0]).abs().max() > 0.05  # the arm moved
    torch.testing.assert_close(trajectories[1], trajectories[0], atol=2e-3, rtol=0)


def test_agent_configs_follow_isaac_lab():
    from simlab.tasks.utils import load_cfg_from_registry

    rsl = load_cfg_from_registry(TASK, "rsl_rl_cfg_entry_point")
    rsl.to_rsl_rl_dict()  # validates: no MISSING field left
    assert (rsl.num_steps_per_env, rsl.max_iterations, rsl.experiment_name) == (16, 1500, "franka_cabinet_direct")
    assert rsl.algorithm.desired_kl == 0.008 and rsl.actor.hidden_dims == [256, 128, 64]
    skrl = load_cfg_from_registry(TASK, "skrl_cfg_entry_point")
    assert skrl["agent"]["rollouts"] == 16 and skrl["trainer"]["timesteps"] == 24000
    rlg = load_cfg_from_registry(TASK, "rl_games_cfg_entry_point")
    assert rlg["params"]["config"]["max_epochs"] == 1500 and rlg["params"]["config"]["torch_compile"] is False
    play = parse_env_cfg("simlab/Franka-Cabinet-Direct-Play-v0", device="cpu")
    assert play.scene.num_envs == 50
