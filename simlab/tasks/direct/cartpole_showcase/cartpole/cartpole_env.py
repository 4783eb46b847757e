"""The direct cartpole with the showcase's spaces (Isaac Lab's ``CartpoleShowcaseEnv``): the actions
become a force on the cart and the joint states an observation of the configured space's kind
(:mod:`.cartpole_env_cfg` lists them). Rewards, terminations and resets are the direct cartpole's."""

from __future__ import annotations

import gymnasium as gym
import torch

from simlab.tasks.direct.cartpole.cartpole_env import CartpoleEnv


def cart_force(actions: torch.Tensor, space: gym.spaces.Space, scale: float) -> torch.Tensor:
    """The force on the cart (num_envs, 1) for a batch of actions from ``space`` (see the config's docstring)."""
    if isinstance(space, gym.spaces.Box):
        return scale * actions
    if isinstance(space, gym.spaces.Discrete):  # (num_envs, 1): 1 backwards, 2 forwards, else none
        return scale * ((actions == 2).float() - (actions == 1).float())
    if isinstance(space, gym.spaces.MultiDiscrete):  # (num_envs, 2): size 0 / half / full, direction
        size = 0.5 * (actions[:, [0]] == 1).float() + (actions[:, [0]] == 2).float()
        return scale * torch.where(actions[:, [1]] == 0, -size, size)
    raise NotImplementedError(
        f"Action space {type(space).__name__} is not one of the showcase's (Box, Discrete, MultiDiscrete)"
    )


def sign_bits(values: torch.Tensor) -> torch.Tensor:
    """1 where a value is >= 0, else 0 (int32, the shape of ``values``)."""
    return (values >= 0).to(torch.int32)


class CartpoleShowcaseEnv(CartpoleEnv):
    def _pre_physics_step(self, actions: torch.Tensor) -> None:
        self.actions = actions.clone()

    def _apply_action(self) -> None:
        force = cart_force(self.actions, self.single_action_space, self.cfg.action_scale)
        self.cartpole.set_joint_effort_target(force, joint_ids=self._cart_dof_idx)

    def _get_observations(self) -> dict:
        space = self.single_observation_space["policy"]
        pole_pos, pole_vel, cart_pos, cart_vel = self._joint_states()
        if isinstance(space, gym.spaces.Box):
            obs = torch.stack((pole_pos, pole_vel, cart_pos, cart_vel), dim=-1)
        elif isinstance(space, (gym.spaces.Discrete, gym.spaces.MultiDiscrete)):
            signs = sign_bits(torch.stack((pole_pos, cart_pos, pole_vel, cart_vel), dim=-1))
            if isinstance(space, gym.spaces.Discrete):  # the four signs as a binary number, pole angle first
                obs = 8 * signs[:, 0] + 4 * signs[:, 1] + 2 * signs[:, 2] + signs[:, 3]  # no new tensor: graphable
            else:
                obs = signs
        elif isinstance(space, gym.spaces.Tuple):
            obs = (self.joint_pos, self.joint_vel)
        elif isinstance(space, gym.spaces.Dict):
            obs = {"joint-positions": self.joint_pos, "joint-velocities": self.joint_vel}
        else:
            raise NotImplementedError(f"Observation space {type(space).__name__} is not one of the showcase's")
        return {"policy": obs}
