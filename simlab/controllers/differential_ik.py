"""Differential inverse kinematics: the joint step that moves a body towards a target pose.

``q_des = q + J^+ dx`` with ``dx`` the task-space error (position, and orientation as an axis-angle
vector) and ``J^+`` an inverse of the body's Jacobian by one of four methods. Everything is torch
over a batch of envs; the ``dls`` and ``trans`` methods use plain elementwise torch ops
(``simlab.controllers.linalg``), so a step that uses them can be captured as a CUDA graph
(``pinv`` and ``svd`` call torch's SVD, which may synchronize).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.utils.math import apply_delta_pose, compute_pose_error, normalize

from .linalg import solve_spd

if TYPE_CHECKING:
    from .differential_ik_cfg import DifferentialIKControllerCfg


class DifferentialIKController:
    """Isaac Lab's differential IK controller: ``set_command``, then ``compute`` each step.

    Frames are the caller's: give the command, the body pose and the Jacobian in one frame
    (usually the robot's root frame). Quaternions are ``(w, x, y, z)``.
    """

    def __init__(self, cfg: DifferentialIKControllerCfg, num_envs: int, device: str):
        cfg.validate()
        self.cfg = cfg
        self.num_envs = num_envs
        self._device = device
        self.ee_pos_des = torch.zeros(num_envs, 3, device=device)
        self.ee_quat_des = torch.zeros(num_envs, 4, device=device)
        self.ee_quat_des[:, 0] = 1.0
        self._command = torch.zeros(num_envs, self.action_dim, device=device)
        self.position_error = torch.zeros(num_envs, 3, device=device)
        """(N, 3) target minus current body position at the last ``compute``: what is left to go."""
        self.orientation_error = torch.zeros(num_envs, 3, device=device)
        """(N, 3) axis-angle rotation from the current to the target orientation at the last ``compute``
        (zero for position commands)."""

    @property
    def action_dim(self) -> int:
        """Size of a command: 3 (position), 6 (relative pose: dx, dy, dz, droll, dpitch, dyaw) or
        7 (absolute pose: x, y, z, qw, qx, qy, qz)."""
        if self.cfg.command_type == "position":
            return 3
        return 6 if self.cfg.use_relative_mode else 7

    def reset(self, env_ids: torch.Tensor | None = None) -> None:
        """Nothing to reset: the controller keeps no state between steps besides the command."""

    def set_command(
        self, command: torch.Tensor, ee_pos: torch.Tensor | None = None, ee_quat: torch.Tensor | None = None
    ) -> None:
        """Set the target from ``command`` (N, action_dim); relative commands need the current pose."""
        if command.ndim != 2 or command.shape[1] != self.action_dim:
            raise ValueError(
                f"DifferentialIKController(command_type={self.cfg.command_type!r},"
                f" use_relative_mode={self.cfg.use_relative_mode}) takes commands of shape (num_envs,"
                f" {self.action_dim}) ({self._layout()}), got {tuple(command.shape)}"
            )
        self._command[:] = command
        relative = self.cfg.use_relative_mode
        if self.cfg.command_type == "position":
            if ee_quat is None:
                raise ValueError("set_command needs ee_quat for position commands (the orientation is held as it is)")
            if relative and ee_pos is None:
                raise ValueError("set_command needs ee_pos for relative position commands")
            self.ee_pos_des[:] = ee_pos + command if relative else command
            self.ee_quat_des[:] = ee_quat
        elif relative:
            if ee_pos is None or ee_quat is None:
                raise ValueError("set_command needs ee_pos and ee_quat for relative pose commands")
            self.ee_pos_des[:], self.ee_quat_des[:] = apply_delta_pose(ee_pos, ee_quat, command)
        else:
            self.ee_pos_des[:] = command[:, 0:3]
            # a policy emits any 4 numbers: the rotation is their direction (unnormalized, the
            # axis-angle error and so the joint step would scale with their length)
            self.ee_quat_des[:] = normalize(command[:, 3:7])

    def compute(
        self, ee_pos: torch.Tensor, ee_quat: torch.Tensor, jacobian: torch.Tensor, joint_pos: torch.Tensor
    ) -> torch.Tensor:
        """Joint position targets (N, num_joints) one IK step towards the target.

        Args:
            ee_pos, ee_quat: current body pose (N, 3), (N, 4).
            jacobian: (N, 6, num_joints) rows ``[linear; angular]``, in the frame of the poses.
            joint_pos: (N, num_joints) current positions of the joints the Jacobian's columns are.
        """
        if jacobian.shape[-1] != joint_pos.shape[-1]:
            raise ValueError(
                f"the Jacobian has {jacobian.shape[-1]} columns but joint_pos has {joint_pos.shape[-1]} joints;"
                " pass the Jacobian columns of the joints being controlled"
            )
        if self.cfg.command_type == "position":
            self.position_error[:] = self.ee_pos_des - ee_pos
            self.orientation_error.zero_()
            delta = self._delta_joint_pos(self.position_error, jacobian[:, 0:3])
        else:
            pos_err, rot_err = compute_pose_error(
                ee_pos, ee_quat, self.ee_pos_des, self.ee_quat_des, rot_error_type="axis_angle"
            )
            self.position_error[:], self.orientation_error[:] = pos_err, rot_err
            delta = self._delta_joint_pos(torch.cat([pos_err, rot_err], dim=1), jacobian)
        return joint_pos + delta

    # -- helpers -------------------------------------------------------------------------------

    def _delta_joint_pos(self, delta_pose: torch.Tensor, jacobian: torch.Tensor) -> torch.Tensor:
        params, method = self.cfg.ik_params, self.cfg.ik_method
        dx = delta_pose.unsqueeze(-1)
        if method == "pinv":
            step = params["k_val"] * torch.linalg.pinv(jacobian) @ dx
        elif method == "svd":
            u, s, vh = torch.linalg.svd(jacobian, full_matrices=False)
            s_inv = torch.where(s > params["min_singular_value"], 1.0 / s.clamp_min(1e-12), torch.zeros_like(s))
            inverse = vh.transpose(-1, -2) @ torch.diag_embed(s_inv) @ u.transpose(-1, -2)
            step = params["k_val"] * inverse @ dx
        elif method == "trans":
            step = params["k_val"] * jacobian.transpose(-1, -2) @ dx
        else:  # dls: J^T (J J^T + lambda^2 I)^-1 dx
            rows = jacobian.shape[1]
            damping = (params["lambda_val"] ** 2) * torch.eye(rows, device=jacobian.device, dtype=jacobian.dtype)
            solution = solve_spd(jacobian @ jacobian.transpose(-1, -2) + damping, dx)
            step = jacobian.transpose(-1, -2) @ solution
        return step.squeeze(-1)

    def _layout(self) -> str:
        return {3: "x, y, z", 6: "dx, dy, dz, droll, dpitch, dyaw", 7: "x, y, z, qw, qx, qy, qz"}[self.action_dim]
