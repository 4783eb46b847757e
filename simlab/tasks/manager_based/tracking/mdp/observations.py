"""Tracking observations: the clip's anchor seen from the robot's anchor; the robot's bodies in its
anchor frame (for the critic)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv


def _anchor_to_clip(env: ManagerBasedRLEnv, command_name: str) -> tuple[torch.Tensor, torch.Tensor]:
    m = env.command_manager.get_term(command_name)
    return math_utils.subtract_frame_transforms(
        m.robot_anchor_pos_w, m.robot_anchor_quat_w, m.anchor_pos_w, m.anchor_quat_w
    )


def motion_anchor_pos_b(env: ManagerBasedRLEnv, command_name: str) -> torch.Tensor:
    """(N, 3) the clip's anchor position in the robot's anchor frame."""
    return _anchor_to_clip(env, command_name)[0]


def motion_anchor_ori_b(env: ManagerBasedRLEnv, command_name: str) -> torch.Tensor:
    """(N, 6) the clip's anchor orientation in the robot's anchor frame: two columns of its rotation matrix."""
    rotation = math_utils.matrix_from_quat(_anchor_to_clip(env, command_name)[1])
    return rotation[..., :2].reshape(rotation.shape[0], -1)


def robot_body_pos_b(env: ManagerBasedRLEnv, command_name: str) -> torch.Tensor:
    """(N, 3 B) the tracked bodies' positions in the robot's anchor frame."""
    m = env.command_manager.get_term(command_name)
    count = m.robot_body_ids.numel()
    pos, _ = math_utils.subtract_frame_transforms(
        m.robot_anchor_pos_w[:, None].expand(-1, count, -1),
        m.robot_anchor_quat_w[:, None].expand(-1, count, -1),
        m.robot_body_pos_w,
        m.robot_body_quat_w,
    )
    return pos.reshape(pos.shape[0], -1)


def robot_body_ori_b(env: ManagerBasedRLEnv, command_name: str) -> torch.Tensor:
    """(N, 6 B) the tracked bodies' orientations in the robot's anchor frame (two matrix columns each)."""
    m = env.command_manager.get_term(command_name)
    count = m.robot_body_ids.numel()
    _, quat = math_utils.subtract_frame_transforms(
        m.robot_anchor_pos_w[:, None].expand(-1, count, -1),
        m.robot_anchor_quat_w[:, None].expand(-1, count, -1),
        m.robot_body_pos_w,
        m.robot_body_quat_w,
    )
    return math_utils.matrix_from_quat(quat)[..., :2].reshape(quat.shape[0], -1)
