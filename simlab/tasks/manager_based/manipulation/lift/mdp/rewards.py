"""Rewards for reaching, lifting and carrying the object to its commanded position."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import SceneEntityCfg
from simlab.utils.math import combine_frame_transforms

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

__all__ = ["object_ee_distance", "object_goal_distance", "object_is_lifted"]

_ROBOT = SceneEntityCfg("robot")
_OBJECT = SceneEntityCfg("object")
_EE_FRAME = SceneEntityCfg("ee_frame")


def object_is_lifted(
    env: ManagerBasedRLEnv, minimal_height: float, object_cfg: SceneEntityCfg = _OBJECT
) -> torch.Tensor:
    """1 where the object's centre is above ``minimal_height`` (world z), else 0."""
    return (env.scene[object_cfg.name].data.root_pos_w[:, 2] > minimal_height).float()


def object_ee_distance(
    env: ManagerBasedRLEnv,
    std: float,
    object_cfg: SceneEntityCfg = _OBJECT,
    ee_frame_cfg: SceneEntityCfg = _EE_FRAME,
) -> torch.Tensor:
    """``1 - tanh(d / std)`` of the distance from the end-effector frame to the object."""
    cube_pos_w = env.scene[object_cfg.name].data.root_pos_w
    ee_w = env.scene[ee_frame_cfg.name].data.target_pos_w[..., 0, :]
    return 1 - torch.tanh(torch.linalg.norm(cube_pos_w - ee_w, dim=1) / std)


def object_goal_distance(
    env: ManagerBasedRLEnv,
    std: float,
    minimal_height: float,
    command_name: str,
    robot_cfg: SceneEntityCfg = _ROBOT,
    object_cfg: SceneEntityCfg = _OBJECT,
) -> torch.Tensor:
    """``1 - tanh(d / std)`` of the object's distance to the commanded position, once lifted."""
    robot, obj = env.scene[robot_cfg.name], env.scene[object_cfg.name]
    command = env.command_manager.get_command(command_name)
    des_pos_w, _ = combine_frame_transforms(robot.data.root_pos_w, robot.data.root_quat_w, command[:, :3])
    distance = torch.linalg.norm(des_pos_w - obj.data.root_pos_w, dim=1)
    return (obj.data.root_pos_w[:, 2] > minimal_height) * (1 - torch.tanh(distance / std))
