"""The solve criteria of the velocity and quadcopter tasks read the right quantities from the env."""

from __future__ import annotations

import gymnasium as gym
import pytest
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.benchmarks.criteria import criterion_for
from simlab.tasks.utils import parse_env_cfg


def _env(task: str, num_envs: int = 4):
    env = gym.make(task, cfg=parse_env_cfg(task, device="cpu", num_envs=num_envs)).unwrapped
    env.reset(seed=0)
    return env


def test_velocity_criterion_is_the_mean_planar_command_error():
    env = _env("simlab/Velocity-Flat-Unitree-Go2-v0")
    try:
        criterion = criterion_for("simlab/Velocity-Flat-Unitree-Go2-v0")
        on_step, sums = criterion.make_hook()
        command = env.command_manager.get_command("base_velocity")
        for offset in (0.0, 0.6):  # commands that the base follows exactly, then 0.6 m/s off in x
            env.step(torch.zeros(4, env.single_action_space.shape[-1]))
            command[:, :2] = env.scene["robot"].data.root_lin_vel_b[:, :2]
            command[:, 0] += offset
            on_step(env, None, None)
        score, passed = criterion.judge({}, sums)
        assert abs(score - 0.3) < 1e-5 and not passed  # (0 + 0.6) / 2 steps > 0.25 m/s
        on_step(env, None, None)  # a third step, still 0.6 off: 0.4 m/s
        assert abs(criterion.judge({}, sums)[0] - 0.4) < 1e-5
    finally:
        env.close()


def test_quadcopter_criterion_counts_settled_steps_near_the_goal():
    env = _env("simlab/Quadcopter-Direct-v0")
    try:
        criterion = criterion_for("simlab/Quadcopter-Direct-v0")
        on_step, counts = criterion.make_hook()
        env.episode_length_buf.zero_()  # the task starts episodes at random lengths: no time-outs here
        settle_steps = round(2.0 / env.step_dt)
        hover = torch.zeros(4, 4)
        hover[:, 0] = 2.0 / env.cfg.thrust_to_weight - 1.0  # thrust = weight: it neither climbs nor falls
        for step in range(settle_steps + 10):
            env.step(hover)
            if step >= settle_steps + 5:  # the last 5 steps: the goal is where the quadcopter is
                env._desired_pos_w.copy_(env._robot.data.root_pos_w)
            on_step(env, None, None)
        assert counts["total"] == 4 * 11  # the first 2 s of each episode do not count
        score, passed = criterion.judge({}, counts)
        assert abs(score - 5 / 11) < 1e-6 and not passed  # hovering away from the goal, then 5 steps at it
    finally:
        env.close()


def test_ant_and_humanoid_criteria_are_the_torso_speed_towards_the_target():
    for task in ("simlab/Ant-v0", "simlab/Humanoid-v0", "simlab/Ant-Direct-v0", "simlab/Humanoid-Direct-v0"):
        assert criterion_for(task).description == "mean torso speed towards the target >= 1 m/s"
    with pytest.raises(ValueError, match="AMP humanoids have none"):
        criterion_for("simlab/Humanoid-AMP-Dance-Direct-v0")
    env = _env("simlab/Ant-v0")
    try:
        criterion = criterion_for("simlab/Ant-v0")
        on_step, sums = criterion.make_hook()
        env.step(torch.zeros(4, env.single_action_space.shape[-1]))  # dropped onto its legs: about still
        on_step(env, None, None)
        speed, passed = criterion.judge({}, sums)
        assert abs(speed) < 0.3 and not passed
        robot = env.scene["robot"]
        running = torch.tensor([[3.0, 0.5, 0.0, 0.0, 0.0, 0.0]]).repeat(4, 1)  # 3 m/s towards +x
        robot.write_root_velocity_to_sim(running)
        on_step(env, None, None)
        score, passed = criterion.judge({}, sums)
        assert abs(score - (speed + 3.0) / 2) < 1e-5 and passed  # the mean over both steps
    finally:
        env.close()
