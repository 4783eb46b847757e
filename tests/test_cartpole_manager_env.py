"""The manager-based cartpole: rewards by hand, time-outs, reset ranges, same-step resets, seeding."""

from __future__ import annotations

import math

import gymnasium as gym
import pytest
import torch

from simlab.envs import ManagerBasedRLEnv
from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleEnvCfg

NUM_ENVS = 4


def make_env(num_envs: int = NUM_ENVS, seed: int | None = 0, **changes) -> ManagerBasedRLEnv:
    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs = num_envs
    cfg.sim.device = "cpu"
    cfg.seed = seed
    for key, value in changes.items():
        setattr(cfg, key, value)
    return ManagerBasedRLEnv(cfg)


def test_config_follows_isaac_lab():
    cfg = CartpoleEnvCfg()
    assert cfg.decimation == 2 and cfg.episode_length_s == 5 and cfg.sim.dt == pytest.approx(1 / 120)
    assert cfg.viewer.eye == (8.0, 0.0, 5.0)
    assert cfg.actions.joint_effort.scale == 100.0
    assert cfg.observations.policy.concatenate_terms and not cfg.observations.policy.enable_corruption


def test_spaces_metadata_and_lengths():
    env = make_env()
    assert isinstance(env, gym.Env)
    assert env.metadata["autoreset_mode"] == gym.vector.AutoresetMode.SAME_STEP
    assert env.metadata["render_modes"] == [None, "human", "rgb_array"]
    assert env.step_dt == pytest.approx(2 / 120) and env.physics_dt == pytest.approx(1 / 120)
    assert env.max_episode_length == math.ceil(5 / (2 / 120)) == 300
    assert env.single_observation_space["policy"].shape == (4,)
    assert env.observation_space["policy"].shape == (NUM_ENVS, 4)
    assert env.single_action_space.shape == (1,) and env.action_space.shape == (NUM_ENVS, 1)
    obs, extras = env.reset()
    assert obs["policy"].shape == (NUM_ENVS, 4)
    obs, rew, term, trunc, extras = env.step(torch.zeros(NUM_ENVS, 1))
    assert rew.shape == term.shape == trunc.shape == (NUM_ENVS,)
    assert term.dtype == trunc.dtype == torch.bool
    env.close()


def test_reward_of_hand_set_states():
    env = make_env()
    env.reset()
    robot = env.scene["robot"]
    # cart position, pole angle, cart velocity, pole velocity per env; env 3 is off the rail bounds.
    pos = torch.tensor([[0.0, 0.0], [0.5, 0.3], [-1.0, 4.0], [3.5, -0.2]])
    vel = torch.tensor([[0.0, 0.0], [1.0, -2.0], [-0.5, 0.7], [0.2, 0.1]])
    robot.write_joint_state_to_sim(pos, vel)
    env.sim.forward()
    env.termination_manager.compute()
    reward = env.reward_manager.compute(dt=env.step_dt)

    terminated = (pos[:, 0].abs() > 3.0).float()
    angle = torch.remainder(pos[:, 1] + math.pi, 2 * math.pi) - math.pi  # 4 rad wraps to 4 - 2 pi
    expected = (
        1.0 * (1 - terminated) - 2.0 * terminated - 1.0 * angle**2 - 0.01 * vel[:, 0].abs() - 0.005 * vel[:, 1].abs()
    ) * env.step_dt
    torch.testing.assert_close(reward, expected, atol=1e-5, rtol=1e-5)
    assert env.termination_manager.terminated.tolist() == [False, False, False, True]
    env.close()


def test_reset_events_sample_within_their_ranges():
    env = make_env(num_envs=64)
    obs, _ = env.reset()
    pos, vel = obs["policy"][:, :2], obs["policy"][:, 2:]
    for values, bound in ((pos[:, 0], 1.0), (vel[:, 0], 0.5), (pos[:, 1], 0.25 * math.pi), (vel[:, 1], 0.25 * math.pi)):
        assert values.abs().max() <= bound + 1e-6
        assert values.std() > bound / 4  # spread over the range, not a constant
    env.close()


def test_time_out_truncates_at_max_episode_length():
    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs = NUM_ENVS
    cfg.sim.device = "cpu"
    # Upright and at rest: the pole stays balanced with zero effort, so only the time-out ends it.
    for term in (cfg.events.reset_cart_position, cfg.events.reset_pole_position):
        term.params["position_range"] = (0.0, 0.0)
        term.params["velocity_range"] = (0.0, 0.0)
    env = ManagerBasedRLEnv(cfg)
    env.reset()
    action = torch.zeros(NUM_ENVS, 1)
    for _ in range(env.max_episode_length - 1):
        _, _, term, trunc, extras = env.step(action)
        assert not term.any() and not trunc.any() and "final_obs" in extras  # every step (docs/env_step.md)
    _, _, term, trunc, extras = env.step(action)
    assert trunc.all() and not term.any()
    assert extras["time_outs"].all()
    assert (env.episode_length_buf == 0).all()
    assert extras["log"]["Episode_Termination/time_out"] == NUM_ENVS
    assert extras["log"]["Episode_Reward/alive"] == pytest.approx(1.0, abs=1e-3)  # 1 per second of episode
    assert "final_obs" in extras
    env.close()


def test_terminated_envs_reset_in_the_same_step_and_keep_final_obs():
    env = make_env()
    env.reset()
    robot = env.scene["robot"]
    # Env 1 starts past the bound: it terminates at the next step and is reset in it.
    pos = robot.data.joint_pos.clone()
    pos[1, 0] = 3.4
    robot.write_joint_state_to_sim(pos, torch.zeros_like(pos))
    env.sim.forward()
    obs, rew, term, trunc, extras = env.step(torch.zeros(NUM_ENVS, 1))
    assert term.tolist() == [False, True, False, False] and not trunc.any()
    final = extras["final_obs"]["policy"]
    assert final[1, 0] > 3.0  # the state the episode ended in
    assert obs["policy"][1, 0].abs() <= 1.0  # already the next episode's first observation
    torch.testing.assert_close(final[[0, 2, 3]], obs["policy"][[0, 2, 3]])
    assert env.episode_length_buf.tolist() == [1, 0, 1, 1]
    assert extras["log"]["Episode_Termination/cart_out_of_bounds"] == 1
    assert rew[1] < 0  # -2 for terminating outweighs +0 alive
    env.close()


def _rollout(seed: int, steps: int = 60) -> torch.Tensor:
    env = make_env(seed=seed)
    obs, _ = env.reset(seed=seed)
    generator = torch.Generator().manual_seed(123)
    out = [obs["policy"].clone()]
    for _ in range(steps):
        obs, *_ = env.step(torch.rand(NUM_ENVS, 1, generator=generator) * 2 - 1)
        out.append(obs["policy"].clone())
    env.close()
    return torch.stack(out)


def test_same_seed_gives_identical_trajectories():
    a, b, c = _rollout(7), _rollout(7), _rollout(8)
    assert torch.equal(a, b)
    assert not torch.equal(a, c)


def test_bad_actions_are_rejected():
    env = make_env()
    env.reset()
    with pytest.raises(ValueError, match=r"shape \(num_envs, action_dim\) = \(4, 1\)"):
        env.step(torch.zeros(NUM_ENVS, 2))
    bad = torch.zeros(NUM_ENVS, 1)
    bad[2, 0] = float("nan")
    with pytest.raises(ValueError, match=r"NaN or inf \(envs \[2\]\)"):
        env.step(bad)
    env.close()


def test_effort_action_moves_the_cart():
    env = make_env()
    env.reset()
    start = env.scene["robot"].data.joint_pos[:, 0].clone()
    for _ in range(10):
        env.step(torch.ones(NUM_ENVS, 1))
    assert (env.scene["robot"].data.joint_pos[:, 0] > start + 0.05).all()
    torch.testing.assert_close(env.scene["robot"].data.joint_effort_target[:, 0], torch.full((NUM_ENVS,), 100.0))
    env.close()
