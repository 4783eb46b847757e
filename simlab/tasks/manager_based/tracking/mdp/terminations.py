"""Tracking terminations: the robot's anchor or end effectors leave the clip (heights), or its anchor
tilts away from the clip's."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

_GRAVITY = (0.0, 0.0, -1.0)


def bad_anchor_pos_z_only(env: ManagerBasedRLEnv, command_name: str, threshold: float) -> torch.Tensor:
    m = env.command_manager.get_term(command_name)
    return torch.abs(m.anchor_pos_w[:, 2] - m.robot_anchor_pos_w[:, 2]) > threshold


def bad_anchor_ori(env: ManagerBasedRLEnv, command_name: str, threshold: float) -> torch.Tensor:
    """The z component of gravity in the clip's anchor frame and in the robot's differ by more than ``threshold``."""
    m = env.command_manager.get_term(command_name)
    gravity = torch.tensor(_GRAVITY, device=env.device).expand(env.num_envs, 3)
    clip_z = math_utils.quat_apply_inverse(m.anchor_quat_w, gravity)[:, 2]
    robot_z = math_utils.quat_apply_inverse(m.robot_anchor_quat_w, gravity)[:, 2]
    return torch.abs(clip_z - robot_z) > threshold


def bad_motion_body_pos_z_only(
    env: ManagerBasedRLEnv, command_name: str, threshold: float, body_names: list[str]
) -> torch.Tensor:
    """One of ``body_names`` (of the command's bodies) is more than ``threshold`` above or below its clip height."""
    m = env.command_manager.get_term(command_name)
    ids = [m.cfg.body_names.index(name) for name in body_names]
    error = torch.abs(m.body_pos_relative_w[:, ids, 2] - m.robot_body_pos_w[:, ids, 2])
    return torch.any(error > threshold, dim=-1)
