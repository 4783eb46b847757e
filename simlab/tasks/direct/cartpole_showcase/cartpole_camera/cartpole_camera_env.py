"""The direct camera cartpole with the showcase's spaces (Isaac Lab's ``CartpoleCameraShowcaseEnv``):
the image alone, or with the joint velocities in a Dict or Tuple; actions as the state showcase's."""

from __future__ import annotations

import gymnasium as gym
import torch

from simlab.tasks.direct.cartpole.cartpole_camera_env import CartpoleCameraEnv

from ..cartpole.cartpole_env import cart_force


class CartpoleCameraShowcaseEnv(CartpoleCameraEnv):
    def _pre_physics_step(self, actions: torch.Tensor) -> None:
        self.actions = actions.clone()

    def _apply_action(self) -> None:
        force = cart_force(self.actions, self.single_action_space, self.cfg.action_scale)
        self.cartpole.set_joint_effort_target(force, joint_ids=self._cart_dof_idx)

    def _get_observations(self) -> dict:
        image = super()._get_observations()["policy"]
        space = self.single_observation_space["policy"]
        if isinstance(space, gym.spaces.Box):
            obs = image
        elif isinstance(space, gym.spaces.Tuple):
            obs = (image, self.joint_vel)
        elif isinstance(space, gym.spaces.Dict):
            obs = {"joint-velocities": self.joint_vel, "camera": image}
        else:
            raise NotImplementedError(f"Observation space {type(space).__name__} is not one of the camera showcase's")
        return {"policy": obs}
