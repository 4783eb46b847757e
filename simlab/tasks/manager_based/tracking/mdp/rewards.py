"""Tracking rewards: ``exp(-error / std^2)`` of the anchor's and the bodies' pose and velocity errors
to the clip (bodies compared in the robot's frame, see :class:`MotionCommand`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

    from .commands import MotionCommand


def _motion(env: ManagerBasedRLEnv, command_name: str) -> MotionCommand:
    return env.command_manager.get_term(command_name)


def motion_global_anchor_position_error_exp(env: ManagerBasedRLEnv, command_name: str, std: float) -> torch.Tensor:
    m = _motion(env, command_name)
    error = torch.sum(torch.square(m.anchor_pos_w - m.robot_anchor_pos_w), dim=-1)
    return torch.exp(-error / std**2)


def motion_global_anchor_orientation_error_exp(env: ManagerBasedRLEnv, command_name: str, std: float) -> torch.Tensor:
    m = _motion(env, command_name)
    error = math_utils.quat_error_magnitude(m.anchor_quat_w, m.robot_anchor_quat_w) ** 2
    return torch.exp(-error / std**2)


def motion_relative_body_position_error_exp(env: ManagerBasedRLEnv, command_name: str, std: float) -> torch.Tensor:
    m = _motion(env, command_name)
    error = torch.sum(torch.square(m.body_pos_relative_w - m.robot_body_pos_w), dim=-1).mean(-1)
    return torch.exp(-error / std**2)


def motion_relative_body_orientation_error_exp(env: ManagerBasedRLEnv, command_name: str, std: float) -> torch.Tensor:
    m = _motion(env, command_name)
    error = (math_utils.quat_error_magnitude(m.body_quat_relative_w, m.robot_body_quat_w) ** 2).mean(-1)
    return torch.exp(-error / std**2)


def motion_global_body_linear_velocity_error_exp(env: ManagerBasedRLEnv, command_name: str, std: float) -> torch.Tensor:
    m = _motion(env, command_name)
    error = torch.sum(torch.square(m.body_lin_vel_w - m.robot_body_lin_vel_w), dim=-1).mean(-1)
    return torch.exp(-error / std**2)


def motion_global_body_angular_velocity_error_exp(
    env: ManagerBasedRLEnv, command_name: str, std: float
) -> torch.Tensor:
    m = _motion(env, command_name)
    error = torch.sum(torch.square(m.body_ang_vel_w - m.robot_body_ang_vel_w), dim=-1).mean(-1)
    return torch.exp(-error / std**2)
