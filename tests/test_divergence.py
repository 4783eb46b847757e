"""A world whose physics blows up is put back, ends its episode and is counted; or the step raises."""

from __future__ import annotations

import pytest
import torch

from simlab.envs import ManagerBasedRLEnv
from simlab.envs.utils.cuda_graph import SimulationDivergedError
from simlab.tasks.direct.cartpole.cartpole_env import CartpoleEnv, CartpoleEnvCfg
from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleEnvCfg as ManagerCartpoleCfg


def direct_cartpole(num_envs: int = 6) -> CartpoleEnv:
    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs = num_envs
    cfg.sim.device = "cpu"
    cfg.seed = 1
    return CartpoleEnv(cfg)


@pytest.mark.parametrize("bad_value", [float("nan"), 1e20])
def test_a_blown_up_world_ends_its_episode_and_is_counted(bad_value):
    env = direct_cartpole()
    env.reset()
    for _ in range(3):
        env.step(torch.zeros(6, 1))
    before = env.sim.physics.data("qpos").clone()
    env.sim.physics.data("qvel")[3, 1] = bad_value  # what a too-stiff gain or a huge action leads to
    obs, reward, terminated, truncated, extras = env.step(torch.zeros(6, 1))
    assert terminated.tolist() == [False, False, False, True, False, False]
    assert int(extras["log"]["Physics/diverged"]) == 1
    assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
    assert env.episode_length_buf[3] == 0  # reset in the same step, as any finished episode
    assert not torch.equal(env.sim.physics.data("qpos")[0], before[0])  # the others went on stepping
    first_log = extras["log"]
    obs, *_, extras = env.step(torch.zeros(6, 1))
    assert int(extras["log"]["Physics/diverged"]) == 0
    assert int(first_log["Physics/diverged"]) == 1  # each step's log is its own (loggers keep one per step)
    env.close()


def test_on_divergence_raise_stops_with_a_message():
    env = direct_cartpole()
    env.sim.on_divergence = "raise"
    env.reset()
    env.sim.physics.data("qvel")[2, 0] = float("nan")
    with pytest.raises(SimulationDivergedError, match="1 world"):
        env.step(torch.zeros(6, 1))
    with pytest.raises(ValueError, match="'reset' or 'raise'"):
        env.sim.on_divergence = "ignore"
    env.close()


def test_manager_based_env_logs_divergence():
    cfg = ManagerCartpoleCfg()
    cfg.scene.num_envs = 4
    cfg.sim.device = "cpu"
    env = ManagerBasedRLEnv(cfg)
    env.reset(seed=0)
    env.sim.physics.data("qvel")[1, 0] = 1e20
    _, _, terminated, _, extras = env.step(torch.zeros(4, 1))
    assert terminated[1] and int(extras["log"]["Physics/diverged"]) == 1
    assert torch.isfinite(env.sim.physics.data("qvel")).all()
    env.close()


def test_a_control_mujoco_would_zero_counts_as_divergence():
    """MuJoCo zeroes a control above 1e10 with a console warning only: simlab counts it."""
    env = direct_cartpole()
    env.reset()
    action = torch.zeros(6, 1)
    action[4] = 1e12  # times action_scale: far above MuJoCo's limit
    _, _, terminated, _, extras = env.step(action)
    assert terminated[4] and int(extras["log"]["Physics/diverged"]) == 1
    env.close()


def test_check_finite_actions_false_skips_the_action_check():
    """The manager-based cfg's ``check_finite_actions`` still turns the action check off."""
    cfg = ManagerCartpoleCfg()
    cfg.scene.num_envs = 4
    cfg.sim.device = "cpu"
    cfg.check_finite_actions = False
    env = ManagerBasedRLEnv(cfg)
    env.reset(seed=0)
    action = torch.zeros(4, 1)
    action[0] = float("nan")
    env.step(action)  # no ValueError about the action: the user turned the check off
    assert env._stepper._check_actions is False
    env.close()
