"""Run a multi-agent environment with a single-agent learner (Isaac Lab's ``multi_agent_to_single_agent``)."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
import torch

from ..direct_marl_env import DirectMARLEnv, all_agents
from ..direct_rl_env import DirectRLEnv


def multi_agent_to_single_agent(env: DirectMARLEnv, state_as_observation: bool = False) -> DirectRLEnv:
    """A single-agent view of ``env``: one policy acts for all agents.

    * the action is split, in ``possible_agents`` order, into each agent's action;
    * the observation is the agents' observations concatenated in that order, or with
      ``state_as_observation`` the env's shared state (``env.state()``);
    * the reward is the sum of the agents' rewards; terminated and truncated are set where they are
      set for every agent;
    * ``extras["final_obs"]`` and ``extras["time_outs"]`` follow the single-agent convention,
      ``extras["agents"]`` keeps the per-agent extras.

    Spaces must be flat (Box, Discrete, MultiDiscrete) for the concatenation.
    """
    return _SingleAgentEnv(env, state_as_observation)


class _SingleAgentEnv(DirectRLEnv):
    """A :class:`DirectRLEnv` face over a :class:`DirectMARLEnv`; it owns no simulation of its own."""

    def __init__(self, env: DirectMARLEnv, state_as_observation: bool):  # noqa: D107 - no super().__init__
        self.env: DirectMARLEnv = env.unwrapped
        self._state_as_observation = state_as_observation
        if state_as_observation and not self.env.cfg.state_space:
            raise ValueError(
                "state_as_observation needs a shared state, but the env's state_space is 0 (none): "
                "set state_space to -1 (concatenated observations) or to a space"
            )
        self.cfg = self.env.cfg
        self.sim = self.env.sim
        self.scene = self.env.scene
        self.render_mode = self.env.render_mode
        self.metadata = self.env.metadata
        self._is_closed = False
        self._agents = list(self.env.possible_agents)

        self.single_observation_space = gym.spaces.Dict()
        if state_as_observation:
            self.single_observation_space["policy"] = self.env.state_space
        else:
            self.single_observation_space["policy"] = gym.spaces.flatten_space(
                gym.spaces.Tuple([self.env.observation_spaces[a] for a in self._agents])
            )
        self.single_action_space = gym.spaces.flatten_space(
            gym.spaces.Tuple([self.env.action_spaces[a] for a in self._agents])
        )
        self.observation_space = gym.vector.utils.batch_space(self.single_observation_space["policy"], self.num_envs)
        self.action_space = gym.vector.utils.batch_space(self.single_action_space, self.num_envs)
        self.state_space = None
        self._action_sizes = [gym.spaces.flatdim(self.env.action_spaces[a]) for a in self._agents]
        self.extras: dict[str, Any] = {}

    # the MARL env keeps the counters and buffers
    episode_length_buf = property(lambda self: self.env.episode_length_buf)
    common_step_counter = property(lambda self: self.env.common_step_counter)
    reset_buf = property(lambda self: self.env.reset_buf)
    actions = property(
        lambda self: torch.cat([self.env.actions[a].reshape(self.num_envs, -1) for a in self._agents], dim=-1)
    )

    def reset(self, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[dict, dict]:
        obs, extras = self.env.reset(seed, options)
        self.extras = {"agents": extras}
        return self._policy_obs(obs), self.extras

    def step(self, action: torch.Tensor) -> tuple[dict, torch.Tensor, torch.Tensor, torch.Tensor, dict]:
        if not isinstance(action, torch.Tensor):
            action = torch.as_tensor(np.asarray(action), device=self.device)
        expected = (self.num_envs, sum(self._action_sizes))
        if tuple(action.shape) != expected:
            raise ValueError(
                f"Expected actions of shape {expected} (num_envs, summed agent actions), got {tuple(action.shape)}"
            )
        actions = dict(zip(self._agents, torch.split(action, self._action_sizes, dim=-1)))

        obs, rewards, terminated, time_outs, extras = self.env.step(actions)
        self.reward_buf = sum(rewards.values())
        self.reset_terminated = all_agents(terminated)
        self.reset_time_outs = all_agents(time_outs)
        self.obs_buf = self._policy_obs(obs)
        final = {a: extras[a].get("final_obs", obs[a]) for a in self._agents}
        self.extras["final_obs"] = self._policy_obs(final, state=self.env.final_state_buf)
        self.extras["time_outs"] = self.reset_time_outs
        self.extras["agents"] = extras
        return self.obs_buf, self.reward_buf, self.reset_terminated, self.reset_time_outs, self.extras

    def __del__(self):
        pass  # the view does not own the multi-agent env: closing it is the caller's choice

    def render(self, recompute: bool = False) -> np.ndarray | None:
        return self.env.render(recompute)

    def close(self) -> None:
        if not self._is_closed:
            self.env.close()
            self._is_closed = True

    def _policy_obs(self, obs: dict[str, torch.Tensor], state: torch.Tensor | None = None) -> dict:
        if self._state_as_observation:
            return {"policy": state if state is not None else self.env.state()}
        return {"policy": torch.cat([obs[a].reshape(self.num_envs, -1) for a in self._agents], dim=-1)}
