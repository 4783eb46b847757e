"""Isaac Sim's ``torch.rotations``: quaternion algebra (w, x, y, z) and the locomotion helpers."""

from __future__ import annotations

import torch

from simlab.utils.math import (
    euler_xyz_from_quat,
    normalize,
    quat_apply,
    quat_apply_inverse,
    quat_conjugate,
    quat_from_angle_axis,
    quat_from_euler_xyz,
    quat_mul,
)

__all__ = [
    "compute_heading_and_up",
    "compute_rot",
    "get_euler_xyz",
    "normalize_angle",
    "quat_apply",
    "quat_conjugate",
    "quat_from_angle_axis",
    "quat_from_euler_xyz",
    "quat_mul",
    "quat_rotate",
    "quat_rotate_inverse",
]

quat_rotate = quat_apply
quat_rotate_inverse = quat_apply_inverse


def get_euler_xyz(q: torch.Tensor, extrinsic: bool = True) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """``(roll, pitch, yaw)`` of extrinsic X-Y-Z rotations, each in ``[0, 2 pi)``."""
    if not extrinsic:
        raise NotImplementedError("get_euler_xyz(q, extrinsic=False): only extrinsic X-Y-Z angles are provided.")
    return euler_xyz_from_quat(q, wrap_to_2pi=True)


def normalize_angle(x: torch.Tensor) -> torch.Tensor:
    """Angles wrapped to ``(-pi, pi]``."""
    return torch.atan2(torch.sin(x), torch.cos(x))


def compute_heading_and_up(
    torso_rotation: torch.Tensor,
    inv_start_rot: torch.Tensor,
    to_target: torch.Tensor,
    vec0: torch.Tensor,
    vec1: torch.Tensor,
    up_idx: int,
) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor]:
    """The torso's orientation relative to its start (``torso_quat``), how upright it is (``up_proj``: the
    ``up_idx`` component of the torso's ``vec1`` axis), how much it faces ``to_target`` (``heading_proj``:
    its ``vec0`` axis on the unit target direction), and those two axes in the world frame."""
    torso_quat = quat_mul(torso_rotation, inv_start_rot)
    up_vec = quat_apply(torso_quat, vec1)
    heading_vec = quat_apply(torso_quat, vec0)
    up_proj = up_vec[:, up_idx]
    heading_proj = torch.sum(heading_vec * normalize(to_target), dim=-1)
    return torso_quat, up_proj, heading_proj, up_vec, heading_vec


def compute_rot(
    torso_quat: torch.Tensor,
    velocity: torch.Tensor,
    ang_velocity: torch.Tensor,
    targets: torch.Tensor,
    torso_positions: torch.Tensor,
) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor]:
    """Torso-frame linear and angular velocities, the torso's roll, pitch and yaw (``[0, 2 pi)``), and the
    angle from its yaw to the direction of ``targets`` in the ground plane."""
    vel_loc = quat_apply_inverse(torso_quat, velocity)
    angvel_loc = quat_apply_inverse(torso_quat, ang_velocity)
    roll, pitch, yaw = get_euler_xyz(torso_quat)
    walk_target_angle = torch.atan2(targets[:, 1] - torso_positions[:, 1], targets[:, 0] - torso_positions[:, 0])
    return vel_loc, angvel_loc, roll, pitch, yaw, walk_target_angle - yaw
