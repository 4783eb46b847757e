"""Terminations of the lift task."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import SceneEntityCfg
from simlab.utils.math import combine_frame_transforms

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

__all__ = ["object_reached_goal"]

_ROBOT = SceneEntityCfg("robot")
_OBJECT = SceneEntityCfg("object")


def object_reached_goal(
    env: ManagerBasedRLEnv,
    command_name: str = "object_pose",
    threshold: float = 0.02,
    robot_cfg: SceneEntityCfg = _ROBOT,
    object_cfg: SceneEntityCfg = _OBJECT,
) -> torch.Tensor:
    """The object is within ``threshold`` metres of the commanded position."""
    robot, obj = env.scene[robot_cfg.name], env.scene[object_cfg.name]
    command = env.command_manager.get_command(command_name)
    des_pos_w, _ = combine_frame_transforms(robot.data.root_pos_w, robot.data.root_quat_w, command[:, :3])
    return torch.linalg.norm(des_pos_w - obj.data.root_pos_w, dim=1) < threshold
