"""The SE(3) command layout Isaac Lab's devices return: a position delta, a rotation vector, the gripper."""

from __future__ import annotations

import torch

from simlab.utils.math import axis_angle_from_quat, matrix_from_euler, quat_from_matrix

__all__ = ["GRIPPER_CLOSE", "GRIPPER_OPEN", "se3_command"]

GRIPPER_OPEN = 1.0
GRIPPER_CLOSE = -1.0


def se3_command(
    delta_pos: torch.Tensor, delta_euler: torch.Tensor, close_gripper: bool, gripper_term: bool, device: str
) -> torch.Tensor:
    """``[dx, dy, dz, rx, ry, rz(, gripper)]``: the roll-pitch-yaw delta (intrinsic X, Y, Z, as Isaac
    Lab's ``Rotation.from_euler("XYZ")``) as a rotation vector; the gripper +1 open, -1 close."""
    delta_pos = torch.as_tensor(delta_pos, dtype=torch.float32)
    delta_euler = torch.as_tensor(delta_euler, dtype=torch.float32)
    rotation = matrix_from_euler(delta_euler.unsqueeze(0), "XYZ")
    rot_vec = axis_angle_from_quat(quat_from_matrix(rotation))[0]
    parts = [delta_pos, rot_vec]
    if gripper_term:
        parts.append(torch.tensor([GRIPPER_CLOSE if close_gripper else GRIPPER_OPEN]))
    return torch.cat(parts).to(device)
