"""The manager-based ant and humanoid: shapes, reward values on hand-set states, resets by mask, training."""

from __future__ import annotations

import glob
import math

import gymnasium as gym
import pytest
import torch

import simlab.tasks  # noqa: F401 - registers the task ids
from simlab.cli.main import main
from simlab.envs import ManagerBasedRLEnv
from simlab.tasks.utils import parse_env_cfg

NUM_ENVS = 4
# task -> (observation size, action size, fall height of the termination term)
TASKS = {"simlab/Ant-v0": (36, 8, 0.31), "simlab/Humanoid-v0": (75, 21, 0.8)}


def make_env(task: str) -> ManagerBasedRLEnv:
    cfg = parse_env_cfg(task, device="cpu", num_envs=NUM_ENVS)
    cfg.seed = 0
    return gym.make(task, cfg=cfg).unwrapped


def upright_pose(x: torch.Tensor, y: torch.Tensor, z: float, tilt: torch.Tensor | None = None) -> torch.Tensor:
    """Root poses at world (x, y, z), rotated by ``tilt`` (radians) about the world y axis."""
    tilt = torch.zeros_like(x) if tilt is None else tilt
    quat = torch.stack([torch.cos(tilt / 2), torch.zeros_like(x), torch.sin(tilt / 2), torch.zeros_like(x)], dim=-1)
    pos = torch.stack([x, y, torch.full_like(x, z)], dim=-1)
    return torch.cat([pos, quat], dim=-1)


@pytest.mark.parametrize("task", TASKS)
def test_steps_with_isaac_lab_shapes(task):
    num_obs, num_actions, _ = TASKS[task]
    env = make_env(task)
    assert env.graph_blockers() == []
    obs, _ = env.reset()
    assert obs["policy"].shape == (NUM_ENVS, num_obs)
    assert env.action_space.shape == (NUM_ENVS, num_actions)
    for _ in range(10):
        obs, reward, terminated, truncated, _ = env.step(2 * torch.rand(NUM_ENVS, num_actions) - 1)
        assert obs["policy"].isfinite().all() and reward.isfinite().all()
        assert reward.shape == terminated.shape == truncated.shape == (NUM_ENVS,)
    assert set(env.reward_manager.active_terms) == {
        "progress", "alive", "upright", "move_to_target", "action_l2", "energy", "joint_pos_limits"
    }  # fmt: skip
    env.close()


def test_progress_and_upright_rewards_of_hand_set_states():
    env = make_env("simlab/Ant-v0")
    env.reset()
    robot, origins = env.scene["robot"], env.scene.env_origins
    progress = env.reward_manager.get_term_cfg("progress")
    upright = env.reward_manager.get_term_cfg("upright")
    target_x = progress.params["target_pos"][0]

    # start at x = 0..3 m from each env's origin, then move by dx; the height change must not count
    start_x, y = origins[:, 0] + torch.tensor([0.0, 1.0, 2.0, 3.0]), origins[:, 1]
    dx = torch.tensor([0.5, -0.25, 0.0, 1.0])
    robot.write_root_pose_to_sim(upright_pose(start_x, y, 0.5))
    progress.func.reset(torch.ones(NUM_ENVS, dtype=torch.bool))
    tilt = torch.tensor([0.0, math.radians(20.0), math.radians(30.0), math.pi])  # cos: 1, 0.94, 0.87, -1
    robot.write_root_pose_to_sim(upright_pose(start_x + dx, y, 0.7, tilt))
    env.sim.forward()

    # the distance is measured in the plane, to the target in the world frame
    before = torch.hypot(target_x - start_x, y)
    after = torch.hypot(target_x - start_x - dx, y)
    expected_progress = (before - after) / env.step_dt
    torch.testing.assert_close(progress.func(env, **progress.params), expected_progress, rtol=1e-5, atol=2e-3)
    assert upright.func(env, **upright.params).tolist() == [1.0, 1.0, 0.0, 0.0]
    env.close()


@pytest.mark.parametrize("task", TASKS)
def test_fallen_env_resets_by_mask(task):
    num_obs, num_actions, fall_height = TASKS[task]
    env = make_env(task)
    env.reset()
    zeros = torch.zeros(NUM_ENVS, num_actions)
    for _ in range(3):
        env.step(zeros)
    robot = env.scene["robot"]
    progress = env.reward_manager.get_term_cfg("progress").func
    lengths_before = env.episode_length_buf.clone()
    progress.potentials += 1000.0  # a marker the reset must leave alone outside env 2
    potentials_before = progress.potentials.clone()

    pose = robot.data.root_state_w[:, :7].clone()
    pose[2, 2] = 0.3 * fall_height  # env 2's torso well below the fall height
    robot.write_root_pose_to_sim(pose)
    obs, _, terminated, truncated, extras = env.step(zeros)

    assert terminated.tolist() == [False, False, True, False] and not truncated.any()
    assert extras["final_obs"]["policy"][2, 0] < fall_height  # base height of the finished episode
    assert obs["policy"][2, 0] > fall_height  # the next episode starts standing
    assert env.episode_length_buf.tolist() == [int(n) + 1 if i != 2 else 0 for i, n in enumerate(lengths_before)]
    # env 2's potential restarts at its new distance; the others keep their history
    new_distance = torch.hypot(1000.0 - robot.data.root_pos_w[2, 0], robot.data.root_pos_w[2, 1])
    torch.testing.assert_close(progress.potentials[2], -new_distance / env.step_dt)
    others = [0, 1, 3]
    assert torch.equal(progress.prev_potentials[others], potentials_before[others])
    assert progress.prev_potentials[2] == progress.potentials[2]
    env.close()


def test_train_ant_two_iterations(tmp_path):
    argv = ["train", "--task", "simlab/Ant-v0", "--num_envs", "8", "--max_iterations", "2"]
    assert main([*argv, "--device", "cpu", "--headless", "--log_root", str(tmp_path / "logs")]) == 0
    assert glob.glob(str(tmp_path / "logs" / "rsl_rl" / "ant" / "*" / "model_*.pt"))


def test_listed(capsys):
    assert main(["list", "--keyword", "v0"]) == 0
    out = capsys.readouterr().out
    assert "simlab/Ant-v0" in out and "simlab/Humanoid-v0" in out
