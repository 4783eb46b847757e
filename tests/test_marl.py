"""DirectMARLEnv (on the cart double pendulum) and its single-agent conversion."""

from __future__ import annotations

import math

import gymnasium as gym
import pytest
import torch

from simlab.envs import DirectMARLEnv, DirectRLEnv, multi_agent_to_single_agent
from simlab.tasks.direct.cart_double_pendulum.cart_double_pendulum_env import (
    CartDoublePendulumEnv,
    CartDoublePendulumEnvCfg,
    compute_rewards,
)


def make(num_envs: int = 3, **fields) -> CartDoublePendulumEnv:
    cfg = CartDoublePendulumEnvCfg(seed=0, **fields)
    cfg.scene.num_envs = num_envs
    cfg.sim.device = "cpu"
    return CartDoublePendulumEnv(cfg)


def zero_actions(env, n: int) -> dict[str, torch.Tensor]:
    return {agent: torch.zeros(n, 1) for agent in env.possible_agents}


def test_agents_and_spaces():
    env = make()
    assert isinstance(env, DirectMARLEnv)
    assert env.possible_agents == ["cart", "pendulum"] and env.max_num_agents == 2
    assert env.observation_space("cart").shape == (4,) and env.observation_space("pendulum").shape == (3,)
    assert env.action_space("cart").shape == (1,) and env.action_spaces["pendulum"].shape == (1,)
    assert env.state_space.shape == (7,)  # state_space=-1: both observations
    assert env.metadata["autoreset_mode"] == gym.vector.AutoresetMode.SAME_STEP


def test_step_takes_and_returns_per_agent_dicts():
    env = make()
    obs, extras = env.reset()
    assert obs["cart"].shape == (3, 4) and obs["pendulum"].shape == (3, 3)
    assert env.agents == ["cart", "pendulum"] and env.num_agents == 2
    obs, rewards, terminated, truncated, extras = env.step(zero_actions(env, 3))
    for result in (obs, rewards, terminated, truncated, extras):
        assert set(result) == {"cart", "pendulum"}
    assert rewards["cart"].shape == terminated["pendulum"].shape == (3,)
    state = env.state()
    torch.testing.assert_close(state, torch.cat([obs["cart"], obs["pendulum"]], dim=-1))


def test_each_agent_drives_its_own_joint():
    env = make(num_envs=2)
    env.reset()
    env.step({"cart": torch.tensor([[0.5], [-1.0]]), "pendulum": torch.tensor([[1.0], [0.2]])})
    effort = env.robot.data.joint_effort_target
    cart, pole, pendulum = env._cart_dof_idx[0], env._pole_dof_idx[0], env._pendulum_dof_idx[0]
    torch.testing.assert_close(effort[:, cart], torch.tensor([50.0, -100.0]))
    torch.testing.assert_close(effort[:, pendulum], torch.tensor([50.0, 10.0]))
    assert not effort[:, pole].any()


def test_rewards_of_hand_set_states():
    env = make(num_envs=1)
    env.reset()
    pos = torch.tensor([[1.0, 0.2, 0.3]])  # cart, pole, pendulum (MuJoCo order)
    vel = torch.tensor([[2.0, -1.0, 0.5]])
    assert env.robot.joint_names == ["slider_to_cart", "cart_to_pole", "pole_to_pendulum"]
    env.robot.write_joint_state_to_sim(pos, vel)
    env.terminated_dict, env.time_out_dict = env._get_dones()
    rewards = env._get_rewards()
    cart = 1.0 - 0.2**2 - 0.01 * 2.0 - 0.01 * 1.0
    pendulum = 1.0 - (0.2 + 0.3) ** 2 - 0.01 * 0.5
    assert rewards["cart"].item() == pytest.approx(cart, abs=1e-5)
    assert rewards["pendulum"].item() == pytest.approx(pendulum, abs=1e-5)
    # angles are wrapped to [-pi, pi) before they are penalized
    wrapped = compute_rewards(1.0, -2.0, 0.0, 0.0, -1.0, 0.0, -1.0, 0.0, torch.zeros(1), torch.zeros(1),
                              torch.tensor([0.1]), torch.zeros(1), torch.tensor([0.0]), torch.zeros(1),
                              torch.tensor([True]))  # fmt: skip
    assert wrapped["cart"].item() == pytest.approx(-2.0 - 0.01, abs=1e-6)


def test_termination_resets_every_agent_and_keeps_final_observations():
    env = make(num_envs=2)
    env.reset()
    pos = env.robot.data.joint_pos.clone()
    pos[0, env._pole_dof_idx[0]] = math.pi / 2 + 0.1
    env.robot.write_joint_state_to_sim(pos, torch.zeros_like(pos))
    obs, rewards, terminated, truncated, extras = env.step(zero_actions(env, 2))
    assert terminated["cart"].tolist() == terminated["pendulum"].tolist() == [True, False]
    assert rewards["cart"][0] < -2.0 and rewards["pendulum"][0] < -2.0  # termination penalty, no alive bonus
    assert env.episode_length_buf.tolist() == [0, 1]
    assert extras["cart"]["final_obs"][0, 2] > math.pi / 2  # the pole angle that ended the episode
    assert obs["cart"][0, 2].abs() <= 0.25 * math.pi + 1e-6
    torch.testing.assert_close(env.final_state_buf[:, :4], extras["cart"]["final_obs"])


def test_missing_or_unknown_agent_actions_are_errors():
    env = make(num_envs=1)
    env.reset()
    with pytest.raises(KeyError, match="pendulum"):
        env.step({"cart": torch.zeros(1, 1)})
    with pytest.raises(KeyError, match="unknown agents"):
        env.step({**zero_actions(env, 1), "pole": torch.zeros(1, 1)})
    with pytest.raises(ValueError, match="observation_spaces"):
        make(observation_spaces={"cart": 4})


def test_single_agent_conversion_concatenates_and_splits():
    marl = make(num_envs=2)
    env = multi_agent_to_single_agent(marl)
    assert isinstance(env, DirectRLEnv)
    assert env.num_envs == 2 and env.device == "cpu" and env.step_dt == marl.step_dt
    assert env.single_observation_space["policy"].shape == (7,) and env.single_action_space.shape == (2,)
    assert env.observation_space.shape == (2, 7) and env.action_space.shape == (2, 2)
    obs, _ = env.reset()
    assert obs["policy"].shape == (2, 7)
    obs, reward, terminated, truncated, extras = env.step(torch.tensor([[0.5, 1.0], [-1.0, 0.2]]))
    effort = marl.robot.data.joint_effort_target
    torch.testing.assert_close(effort[:, marl._cart_dof_idx[0]], torch.tensor([50.0, -100.0]))
    torch.testing.assert_close(effort[:, marl._pendulum_dof_idx[0]], torch.tensor([50.0, 10.0]))
    torch.testing.assert_close(reward, marl.reward_dict["cart"] + marl.reward_dict["pendulum"])
    torch.testing.assert_close(obs["policy"], torch.cat([marl.obs_dict["cart"], marl.obs_dict["pendulum"]], dim=-1))
    assert extras["time_outs"] is truncated and extras["final_obs"]["policy"].shape == (2, 7)
    assert terminated.dtype == torch.bool
    with pytest.raises(ValueError, match=r"shape \(2, 2\)"):
        env.step(torch.zeros(2, 1))


def test_single_agent_conversion_with_the_state_as_observation():
    marl = make(num_envs=2)
    env = multi_agent_to_single_agent(marl, state_as_observation=True)
    assert env.single_observation_space["policy"] == marl.state_space
    obs, *_ = env.step(torch.zeros(2, 2))
    torch.testing.assert_close(obs["policy"], marl.state())
    with pytest.raises(ValueError, match="state_space is 0"):
        multi_agent_to_single_agent(make(num_envs=1, state_space=0), state_as_observation=True)


def test_isaaclab_zero_agent_script_loop_runs():
    """Isaac Lab's zero_agent.py reads ``env.action_space.shape`` of the gym-made env and steps one tensor;
    ``env.action_space(agent)`` stays Isaac Lab's per-agent space."""
    import simlab.tasks  # noqa: F401
    from simlab.tasks.utils import parse_env_cfg

    task = "simlab/Cart-Double-Pendulum-Direct-v0"
    env = gym.make(task, cfg=parse_env_cfg(task, device="cpu", num_envs=3))
    try:
        assert env.action_space.shape == (3, 2) and env.unwrapped.action_space("pendulum").shape == (1,)
        env.reset(seed=0)
        actions = torch.zeros(env.action_space.shape, device=env.unwrapped.device)
        actions[:, 0] = 1.0  # the cart's column
        env.step(actions)
        assert torch.equal(env.unwrapped.actions["cart"], torch.ones(3, 1))
        assert torch.equal(env.unwrapped.actions["pendulum"], torch.zeros(3, 1))
        with pytest.raises(ValueError, match=r"\(num_envs, 2\)"):
            env.step(torch.zeros(3, 3))
    finally:
        env.close()
