"""Observations of a torso heading for a far target: heading, uprightness, angle to the target."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils
from simlab.managers import SceneEntityCfg

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv

__all__ = ["base_angle_to_target", "base_heading_proj", "base_up_proj", "base_yaw_roll"]

_ROBOT = SceneEntityCfg("robot")


def to_target_w(env: ManagerBasedEnv, target_pos, asset_cfg: SceneEntityCfg) -> torch.Tensor:
    """World vector from the base to the target: ``(num_envs, 3)``."""
    return math_utils.constant_tensor(target_pos, env.device) - env.scene[asset_cfg.name].data.root_pos_w


def base_yaw_roll(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Yaw and roll of the base in the world frame, in [-pi, pi]: ``(num_envs, 2)``."""
    roll, _, yaw = math_utils.euler_xyz_from_quat(env.scene[asset_cfg.name].data.root_quat_w)
    return torch.stack((math_utils.wrap_to_pi(yaw), math_utils.wrap_to_pi(roll)), dim=-1)


def base_up_proj(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """World z component of the base's up axis (1 upright, -1 upside down): ``(num_envs, 1)``."""
    return -env.scene[asset_cfg.name].data.projected_gravity_b[:, 2:3]


def base_heading_proj(
    env: ManagerBasedEnv, target_pos: tuple[float, float, float], asset_cfg: SceneEntityCfg = _ROBOT
) -> torch.Tensor:
    """Cosine between the base's forward axis and the horizontal direction to the target: ``(num_envs, 1)``."""
    data = env.scene[asset_cfg.name].data
    to_target = to_target_w(env, target_pos, asset_cfg)
    to_target[:, 2] = 0.0
    heading = math_utils.quat_apply(data.root_quat_w, data.FORWARD_VEC_B)
    return torch.sum(heading * math_utils.normalize(to_target), dim=-1, keepdim=True)


def base_angle_to_target(
    env: ManagerBasedEnv, target_pos: tuple[float, float, float], asset_cfg: SceneEntityCfg = _ROBOT
) -> torch.Tensor:
    """Yaw still to turn to face the target, in [-pi, pi]: ``(num_envs, 1)``."""
    to_target = to_target_w(env, target_pos, asset_cfg)
    _, _, yaw = math_utils.euler_xyz_from_quat(env.scene[asset_cfg.name].data.root_quat_w)
    angle = torch.atan2(to_target[:, 1], to_target[:, 0]) - yaw
    return math_utils.wrap_to_pi(angle).unsqueeze(-1)
