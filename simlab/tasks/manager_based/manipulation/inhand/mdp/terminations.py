"""Termination terms of the in-hand task."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import SceneEntityCfg

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

__all__ = ["max_consecutive_success", "object_away_from_goal", "object_away_from_robot"]

_OBJECT = SceneEntityCfg("object")
_ROBOT = SceneEntityCfg("robot")


def max_consecutive_success(env: ManagerBasedRLEnv, num_success: int, command_name: str) -> torch.Tensor:
    """The episode has reached ``num_success`` goals."""
    return env.command_manager.get_term(command_name).metrics["consecutive_success"] >= num_success


def object_away_from_goal(
    env: ManagerBasedRLEnv, threshold: float, command_name: str, object_cfg: SceneEntityCfg = _OBJECT
) -> torch.Tensor:
    """The object is more than ``threshold`` [m] from the goal position."""
    goal_pos_e = env.command_manager.get_term(command_name).command[:, :3]
    object_pos_e = env.scene[object_cfg.name].data.root_pos_w - env.scene.env_origins
    return torch.linalg.norm(object_pos_e - goal_pos_e, ord=2, dim=1) > threshold


def object_away_from_robot(
    env: ManagerBasedRLEnv,
    threshold: float,
    asset_cfg: SceneEntityCfg = _ROBOT,
    object_cfg: SceneEntityCfg = _OBJECT,
) -> torch.Tensor:
    """The object is more than ``threshold`` [m] from the robot's root."""
    robot, obj = env.scene[asset_cfg.name], env.scene[object_cfg.name]
    return torch.linalg.norm(robot.data.root_pos_w - obj.data.root_pos_w, dim=1) > threshold
