# Isaac Lab 3.0's isaaclab_tasks/core/reach/mdp.py (develop), written out under the 3.0 import mapping
# (isaaclab.utils.math -> simlab.v3.utils.math). Nothing else differs: it reads the pose command term's
# ``command`` (x, y, z, qx, qy, qz, qw) and the robot through ``.torch``, as 3.0 code does.

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.v3.utils.math import combine_frame_transforms, compute_pose_error

if TYPE_CHECKING:
    from simlab.v3.envs import ManagerBasedRLEnv


def pose_command_success(
    env: ManagerBasedRLEnv, command_name: str, position_threshold: float, orientation_threshold: float
) -> torch.Tensor:
    """True where the body is within ``position_threshold`` [m] and ``orientation_threshold`` [rad] of the command."""
    command = env.command_manager.get_term(command_name)
    data = command.robot.data
    des_pos_w, des_quat_w = combine_frame_transforms(
        data.root_pos_w.torch, data.root_quat_w.torch, command.command[:, :3], command.command[:, 3:]
    )
    pos_error, rot_error = compute_pose_error(
        des_pos_w, des_quat_w, data.body_pos_w.torch[:, command.body_idx], data.body_quat_w.torch[:, command.body_idx]
    )
    return torch.logical_and(
        torch.linalg.norm(pos_error, dim=-1) < position_threshold,
        torch.linalg.norm(rot_error, dim=-1) < orientation_threshold,
    )
