"""Observations of the object to lift."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import SceneEntityCfg
from simlab.utils.math import subtract_frame_transforms

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

__all__ = ["object_position_in_robot_root_frame"]

_ROBOT = SceneEntityCfg("robot")
_OBJECT = SceneEntityCfg("object")


def object_position_in_robot_root_frame(
    env: ManagerBasedRLEnv,
    robot_cfg: SceneEntityCfg = _ROBOT,
    object_cfg: SceneEntityCfg = _OBJECT,
) -> torch.Tensor:
    """(num_envs, 3) the object's position in the robot's root frame."""
    robot, obj = env.scene[robot_cfg.name], env.scene[object_cfg.name]
    pos_b, _ = subtract_frame_transforms(robot.data.root_pos_w, robot.data.root_quat_w, obj.data.root_pos_w)
    return pos_b
