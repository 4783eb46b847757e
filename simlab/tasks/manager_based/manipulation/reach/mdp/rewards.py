"""Rewards for tracking a commanded end-effector pose (given in the robot's root frame)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import SceneEntityCfg
from simlab.utils.math import combine_frame_transforms, quat_error_magnitude, quat_mul

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

__all__ = [
    "orientation_command_error",
    "orientation_command_error_tanh",
    "position_command_error",
    "position_command_error_tanh",
]


def _position_error(env: ManagerBasedRLEnv, command_name: str, asset_cfg: SceneEntityCfg) -> torch.Tensor:
    asset = env.scene[asset_cfg.name]
    command = env.command_manager.get_command(command_name)
    des_pos_w, _ = combine_frame_transforms(asset.data.root_pos_w, asset.data.root_quat_w, command[:, :3])
    return torch.linalg.norm(asset.data.body_pos_w[:, asset_cfg.body_ids[0]] - des_pos_w, dim=1)


def position_command_error(env: ManagerBasedRLEnv, command_name: str, asset_cfg: SceneEntityCfg) -> torch.Tensor:
    """Distance (m) from the body to the commanded position."""
    return _position_error(env, command_name, asset_cfg)


def position_command_error_tanh(
    env: ManagerBasedRLEnv, std: float, command_name: str, asset_cfg: SceneEntityCfg
) -> torch.Tensor:
    """``1 - tanh(distance / std)``: 1 at the target, falling off over ``std`` metres."""
    return 1 - torch.tanh(_position_error(env, command_name, asset_cfg) / std)


def orientation_command_error(env: ManagerBasedRLEnv, command_name: str, asset_cfg: SceneEntityCfg) -> torch.Tensor:
    """Angle (rad) from the body's orientation to the commanded one."""
    asset = env.scene[asset_cfg.name]
    command = env.command_manager.get_command(command_name)
    des_quat_w = quat_mul(asset.data.root_quat_w, command[:, 3:7])
    return quat_error_magnitude(asset.data.body_quat_w[:, asset_cfg.body_ids[0]], des_quat_w)


def orientation_command_error_tanh(
    env: ManagerBasedRLEnv, std: float, command_name: str, asset_cfg: SceneEntityCfg
) -> torch.Tensor:
    """``1 - tanh(angle / std)``: 1 at the commanded orientation, falling off over ``std`` radians."""
    return 1 - torch.tanh(orientation_command_error(env, command_name, asset_cfg) / std)
