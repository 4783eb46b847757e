"""The manager-based cabinet task (``simlab/Open-Drawer-Franka-*``): its reward terms on hand-set
frames, the tasks' spaces, and Isaac Lab's ``open_cabinet_sm.py`` state machine opening the drawer."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from types import SimpleNamespace

import gymnasium as gym
import pytest
import torch
from test_engine_choice import needs_warp

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.tasks.manager_based.manipulation.cabinet import mdp
from simlab.tasks.utils import parse_env_cfg

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GRIPPER_ALONG_HANDLE = [0.5, 0.5, 0.5, 0.5]  # the handle frame in the world: z along +x, y up


def scene_with(tcp, left_tip, right_tip, tcp_quat, handle, handle_quat, drawer, fingers) -> SimpleNamespace:
    """A stand-in env whose frame transformers and joints read the given values (2 envs)."""

    def frames(positions, quats):
        return SimpleNamespace(data=SimpleNamespace(target_pos_w=positions, target_quat_w=quats))

    ee = frames(torch.stack([tcp, left_tip, right_tip], dim=1), torch.stack([tcp_quat] * 3, dim=1))
    cabinet_frame = frames(handle.unsqueeze(1), handle_quat.unsqueeze(1))
    scene = {
        "ee_frame": ee,
        "cabinet_frame": cabinet_frame,
        "cabinet": SimpleNamespace(data=SimpleNamespace(joint_pos=drawer.unsqueeze(-1))),
        "robot": SimpleNamespace(data=SimpleNamespace(joint_pos=fingers)),
    }
    return SimpleNamespace(scene=scene)


def test_reward_terms_of_hand_set_frames():
    handle = torch.tensor([[0.5, 0.0, 0.7], [0.5, 0.0, 0.7]])
    # env 0: tool centre on the handle, fingertips 2 cm above / below, fingers half closed, drawer 25 cm
    # open; env 1: 30 cm in front of the handle, fingertips both above it, fingers open, drawer shut
    env = scene_with(
        tcp=handle + torch.tensor([[0.0, 0.0, 0.0], [-0.3, 0.0, 0.0]]),
        left_tip=handle + torch.tensor([[0.0, 0.0, 0.02], [-0.3, 0.0, 0.05]]),
        right_tip=handle + torch.tensor([[0.0, 0.0, -0.02], [-0.3, 0.0, 0.01]]),
        tcp_quat=torch.tensor([GRIPPER_ALONG_HANDLE, [1.0, 0.0, 0.0, 0.0]]),
        handle=handle,
        handle_quat=torch.tensor([GRIPPER_ALONG_HANDLE] * 2),
        drawer=torch.tensor([0.25, 0.0]),
        fingers=torch.tensor([[0.02, 0.02], [0.04, 0.04]]),
    )
    drawer_cfg = SimpleNamespace(name="cabinet", joint_ids=[0])
    fingers_cfg = SimpleNamespace(name="robot", joint_ids=[0, 1])
    expected = {
        # (1 / (1 + d^2))^2, doubled within 20 cm
        "approach_ee_handle": (mdp.approach_ee_handle(env, threshold=0.2), [2.0, 1 / 1.09**2]),
        # Isaac Lab's alignment wants the gripper's z along the handle frame's -x and its x along -y: zero
        # for a gripper turned like that frame (as the state machine holds it) and for the identity
        "align_ee_handle": (mdp.align_ee_handle(env), [0.0, 0.0]),
        "align_grasp_around_handle": (mdp.align_grasp_around_handle(env), [1.0, 0.0]),
        "approach_gripper_handle": (mdp.approach_gripper_handle(env, offset=0.04), [0.04, 0.0]),
        "grasp_handle": (mdp.grasp_handle(env, 0.03, 0.04, fingers_cfg), [0.04, 0.0]),
        "open_drawer_bonus": (mdp.open_drawer_bonus(env, drawer_cfg), [0.5, 0.0]),
        "multi_stage_open_drawer": (mdp.multi_stage_open_drawer(env, drawer_cfg), [1.5, 0.0]),
    }
    for name, (value, wanted) in expected.items():
        torch.testing.assert_close(value.float(), torch.tensor(wanted), atol=1e-5, rtol=0, msg=name)


def test_align_ee_handle_is_one_for_a_gripper_along_the_handle_frames_minus_x_and_minus_y():
    # handle frame = world axes; gripper z = -x, gripper x = -y (R columns (0,-1,0), (0,0,1), (-1,0,0))
    env = scene_with(
        *(torch.zeros(1, 3),) * 3,
        tcp_quat=torch.tensor([[0.5, 0.5, -0.5, -0.5]]),
        handle=torch.zeros(1, 3),
        handle_quat=torch.tensor([[1.0, 0.0, 0.0, 0.0]]),
        drawer=torch.zeros(1),
        fingers=torch.zeros(1, 2),
    )
    torch.testing.assert_close(mdp.align_ee_handle(env), torch.tensor([1.0]))


@pytest.mark.parametrize(
    ("task", "obs", "actions"),
    [("simlab/Open-Drawer-Franka-v0", 31, 8), ("simlab/Open-Drawer-Franka-IK-Abs-v0", 31, 8),
     ("simlab/Open-Drawer-Franka-IK-Rel-v0", 30, 7)],
)  # fmt: skip
def test_tasks_build_and_step(task, obs, actions):
    cfg = parse_env_cfg(task, device="cpu", num_envs=2)
    env = gym.make(task, cfg=cfg).unwrapped
    try:
        observations, _ = env.reset(seed=0)
        assert observations["policy"].shape == (2, obs) and env.action_space.shape == (2, actions)
        assert env.graph_blockers() == []
        # the handle frame: 50 cm in front of the robot, 71 cm up, turned like a gripper that holds it
        handle = env.scene["cabinet_frame"].data
        torch.testing.assert_close(
            handle.target_pos_w[:, 0] - env.scene.env_origins, torch.tensor([[0.5, -0.01, 0.71]] * 2), atol=1e-4, rtol=0
        )
        torch.testing.assert_close(
            handle.target_quat_w[:, 0], torch.tensor([GRIPPER_ALONG_HANDLE] * 2), atol=1e-5, rtol=0
        )
        _, reward, *_ = env.step(torch.zeros(2, actions))
        assert torch.isfinite(reward).all()
    finally:
        env.close()


def test_open_cabinet_state_machine_opens_the_drawer():
    """Isaac Lab's state machine script, ported by the import mapping, on two CPU envs for 400 steps."""
    script = os.path.join(ROOT, "scripts", "environments", "state_machine", "open_cabinet_sm.py")
    cmd = [sys.executable, script, "--num_envs", "2", "--headless", "--device", "cpu", "--max_app_steps", "400"]
    cmd += ["--seed", "0"]
    env = {**os.environ, "PYTHONPATH": ROOT}
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr[-3000:]
    states = re.findall(r"envs per state \[([\d, ]+)\]", proc.stdout)
    assert states and states[-1].split(", ")[4] == "2", proc.stdout  # both envs reached OPEN_DRAWER
    widest = re.search(r"widest drawer opening per env \[m\]: \[([^\]]+)\]", proc.stdout)
    assert widest, proc.stdout
    assert all(float(x) > 0.2 for x in widest.group(1).split(", ")), widest.group(0)


@needs_warp
def test_mujoco_warp_on_cpu_steps_the_ik_task_like_mujoco():
    """The GPU backend (on Warp's CPU device) and MuJoCo C agree over the first steps of an IK reach."""
    task = "simlab/Open-Drawer-Franka-IK-Abs-v0"
    observations = []
    for engine in ("mujoco", "mujoco_warp"):
        cfg = parse_env_cfg(task, device="cpu", num_envs=2)
        cfg.sim.engine, cfg.seed = engine, 0
        cfg.observations.policy.enable_corruption = False
        env = gym.make(task, cfg=cfg).unwrapped
        env.reset(seed=0)
        target = torch.tensor([[0.45, 0.0, 0.5, 0.0, 1.0, 0.0, 0.0, 1.0]] * 2)  # hand down, gripper open
        for _ in range(10):
            obs, *_ = env.step(target)
        observations.append(obs["policy"])
        env.close()
    assert (observations[0][:, 9:18]).abs().max() > 0.1  # the arm moves
    torch.testing.assert_close(observations[1], observations[0], atol=1e-4, rtol=0)
