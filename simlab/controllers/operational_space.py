"""Operational-space control: joint torques that make a body behave like a spring-damper in task space.

    tau = J^T Lambda (Kp e - Kd v) + g(q) + (I - J^T Jbar^T) M (kp_n (q_n - q) - kd_n qd) + J^T F

with ``e`` the pose error (position, axis-angle), ``v`` the body velocity, ``Lambda = (J M^-1 J^T)^-1``
the task-space mass matrix (with inertial decoupling; else the identity), ``g`` the gravity torques,
``Jbar = M^-1 J^T Lambda`` the dynamically consistent inverse and ``F`` a wrench target (closed-loop
with ``contact_wrench_stiffness_task``: ``F + Kf (F - f)`` for a measured contact force ``f``). Gains,
targets and the motion / wrench axes are given in a task frame (the root frame unless
``set_command`` gets one) and rotated into the root frame.
Damping gains are ``2 sqrt(kp) * damping_ratio``. All torch over a batch of envs; the matrix inverses
are unrolled Cholesky solves in elementwise ops (``simlab.controllers.linalg``), so the step can be
captured as a CUDA graph.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.utils.math import (
    apply_delta_pose,
    combine_frame_transforms,
    compute_pose_error,
    matrix_from_quat,
    normalize,
)

from .linalg import inverse_spd

if TYPE_CHECKING:
    from .operational_space_cfg import OperationalSpaceControllerCfg


class OperationalSpaceController:
    """Isaac Lab's operational-space controller: ``set_command``, then ``compute`` each step.

    Poses, velocities and the Jacobian are given in one frame (the robot's root frame, ``_b``);
    quaternions are ``(w, x, y, z)``.
    """

    def __init__(self, cfg: OperationalSpaceControllerCfg, num_envs: int, device: str):
        cfg.validate()
        self.cfg = cfg
        self.num_envs = num_envs
        self._device = device
        n = num_envs
        self.target_list = list(cfg.target_types)
        self._motion = any(t in ("pose_abs", "pose_rel") for t in self.target_list)
        self._wrench = "wrench_abs" in self.target_list
        self._motion_axes = torch.tensor(cfg.motion_control_axes_task, dtype=torch.float32, device=device)
        self._wrench_axes = torch.tensor(cfg.contact_wrench_control_axes_task, dtype=torch.float32, device=device)
        stiffness = cfg.contact_wrench_stiffness_task
        self._force_gains = None if stiffness is None else torch.tensor(_six(stiffness), device=device)
        self.task_frame_pose_b = torch.zeros(n, 7, device=device)
        """(N, 7) the frame the targets, gains and axes are given in (identity: the root frame)."""
        self.task_frame_pose_b[:, 3] = 1.0
        self._kp = torch.zeros(n, 6, device=device)
        self._damping_ratio = torch.zeros(n, 6, device=device)
        self._kp[:] = torch.as_tensor(_six(cfg.motion_stiffness_task), device=device)
        self._damping_ratio[:] = torch.as_tensor(_six(cfg.motion_damping_ratio_task), device=device)
        self.desired_ee_pose_b = torch.zeros(n, 7, device=device)
        self.desired_ee_pose_b[:, 3] = 1.0
        self.desired_ee_wrench_task = torch.zeros(n, 6, device=device)
        self.pose_error_b = torch.zeros(n, 6, device=device)
        """(N, 6) position and axis-angle error to the target at the last ``compute``."""

    @property
    def action_dim(self) -> int:
        """Command size: 7 per ``pose_abs``, 6 per ``pose_rel`` / ``wrench_abs``, then 6 stiffnesses
        (``variable_kp``) or 6 stiffnesses and 6 damping ratios (``variable``)."""
        size = sum(7 if t == "pose_abs" else 6 for t in self.target_list)
        return size + {"fixed": 0, "variable_kp": 6, "variable": 12}[self.cfg.impedance_mode]

    def reset(self) -> None:
        """Nothing to reset: the controller keeps no state between steps besides the command."""

    def set_command(
        self,
        command: torch.Tensor,
        current_ee_pose_b: torch.Tensor | None = None,
        current_task_frame_pose_b: torch.Tensor | None = None,
    ) -> None:
        """Set the targets from ``command`` (N, action_dim), laid out as ``action_dim`` says.

        ``pose_rel`` needs the current end-effector pose; targets are in the task frame when
        ``current_task_frame_pose_b`` (N, 7) is given, else in the root frame.
        """
        if command.ndim != 2 or command.shape[1] != self.action_dim:
            raise ValueError(
                f"OperationalSpaceController(target_types={self.target_list}, impedance_mode="
                f"{self.cfg.impedance_mode!r}) takes commands of shape (num_envs, {self.action_dim}), got"
                f" {tuple(command.shape)}"
            )
        if current_task_frame_pose_b is None:
            self.task_frame_pose_b.zero_()
            self.task_frame_pose_b[:, 3] = 1.0
        else:
            self.task_frame_pose_b[:] = current_task_frame_pose_b
        start = 0
        for target in self.target_list:
            if target == "pose_abs":
                # the rotation is the direction of the 4 numbers (a policy's are not unit length)
                pose = torch.cat([command[:, start : start + 3], normalize(command[:, start + 3 : start + 7])], dim=-1)
                start += 7
                if current_task_frame_pose_b is not None:
                    pos, quat = combine_frame_transforms(
                        current_task_frame_pose_b[:, :3], current_task_frame_pose_b[:, 3:], pose[:, :3], pose[:, 3:]
                    )
                    pose = torch.cat([pos, quat], dim=-1)
                self.desired_ee_pose_b[:] = pose
            elif target == "pose_rel":
                if current_ee_pose_b is None:
                    raise ValueError("set_command needs current_ee_pose_b for 'pose_rel' targets")
                pos, quat = apply_delta_pose(
                    current_ee_pose_b[:, :3], current_ee_pose_b[:, 3:], command[:, start : start + 6]
                )
                start += 6
                self.desired_ee_pose_b[:] = torch.cat([pos, quat], dim=-1)
            else:
                self.desired_ee_wrench_task[:] = command[:, start : start + 6]
                start += 6
        low, high = self.cfg.motion_stiffness_limits_task
        if self.cfg.impedance_mode in ("variable_kp", "variable"):
            self._kp[:] = command[:, start : start + 6].clamp(low, high)
            start += 6
        if self.cfg.impedance_mode == "variable":
            low, high = self.cfg.motion_damping_ratio_limits_task
            self._damping_ratio[:] = command[:, start : start + 6].clamp(low, high)

    def compute(
        self,
        jacobian_b: torch.Tensor,
        current_ee_pose_b: torch.Tensor | None = None,
        current_ee_vel_b: torch.Tensor | None = None,
        current_ee_force_b: torch.Tensor | None = None,
        mass_matrix: torch.Tensor | None = None,
        gravity: torch.Tensor | None = None,
        current_joint_pos: torch.Tensor | None = None,
        current_joint_vel: torch.Tensor | None = None,
        nullspace_joint_pos_target: torch.Tensor | None = None,
    ) -> torch.Tensor:
        """Joint efforts (N, num_joints) for the Jacobian's joints."""
        cfg = self.cfg
        n, num_joints = jacobian_b.shape[0], jacobian_b.shape[2]
        efforts = torch.zeros(n, num_joints, device=jacobian_b.device)
        # rotation of the task frame's axes into the root frame, for forces and torques alike
        rot = matrix_from_quat(self.task_frame_pose_b[:, 3:])
        rot6 = torch.zeros(n, 6, 6, device=jacobian_b.device)
        rot6[:, :3, :3] = rot
        rot6[:, 3:, 3:] = rot

        def in_root(diagonal: torch.Tensor) -> torch.Tensor:
            """A diagonal gain or selection matrix of the task frame, expressed in the root frame."""
            return rot6 @ torch.diag_embed(diagonal.expand(n, 6)) @ rot6.transpose(-1, -2)

        decouple = cfg.inertial_dynamics_decoupling or cfg.nullspace_control == "position"
        if decouple and mass_matrix is None:
            raise ValueError("compute needs mass_matrix for inertial_dynamics_decoupling / nullspace_control")
        mass_inv = inverse_spd(mass_matrix) if decouple else None
        jac_t = jacobian_b.transpose(-1, -2)

        if self._motion:
            if current_ee_pose_b is None or current_ee_vel_b is None:
                raise ValueError("compute needs current_ee_pose_b and current_ee_vel_b for pose targets")
            pos_err, rot_err = compute_pose_error(
                current_ee_pose_b[:, :3],
                current_ee_pose_b[:, 3:],
                self.desired_ee_pose_b[:, :3],
                self.desired_ee_pose_b[:, 3:],
                rot_error_type="axis_angle",
            )
            self.pose_error_b[:] = torch.cat([pos_err, rot_err], dim=-1)
            kd = 2.0 * self._kp.sqrt() * self._damping_ratio
            acc = in_root(self._kp) @ self.pose_error_b[..., None] - in_root(kd) @ current_ee_vel_b[..., None]
            acc = (in_root(self._motion_axes) @ acc)[..., 0]
            if cfg.inertial_dynamics_decoupling:
                acc = (self._task_mass_matrix(jacobian_b, mass_inv) @ acc[..., None])[..., 0]
            efforts += (jac_t @ acc[..., None])[..., 0]

        if self._wrench:
            wrench = rot6 @ self.desired_ee_wrench_task[..., None]
            if self._force_gains is not None:
                if current_ee_force_b is None:
                    raise ValueError("compute needs current_ee_force_b (N, 3) with contact_wrench_stiffness_task")
                measured = torch.cat([current_ee_force_b, torch.zeros_like(current_ee_force_b)], dim=-1)
                wrench = wrench + in_root(self._force_gains) @ (wrench - measured[..., None])
            efforts += (jac_t @ in_root(self._wrench_axes) @ wrench)[..., 0]

        if cfg.gravity_compensation:
            if gravity is None:
                raise ValueError("compute needs gravity (the gravity-compensation torques) with gravity_compensation")
            efforts += gravity

        if cfg.nullspace_control == "position":
            if current_joint_pos is None or current_joint_vel is None:
                raise ValueError("compute needs current_joint_pos and current_joint_vel for nullspace_control")
            target = current_joint_pos * 0.0 if nullspace_joint_pos_target is None else nullspace_joint_pos_target
            kp_n = cfg.nullspace_stiffness
            kd_n = 2.0 * kp_n**0.5 * cfg.nullspace_damping_ratio
            joint_acc = kp_n * (target - current_joint_pos) - kd_n * current_joint_vel
            torque = (mass_matrix @ joint_acc[..., None])[..., 0]
            task_mass = inverse_spd(jacobian_b @ mass_inv @ jac_t)
            jbar = mass_inv @ jac_t @ task_mass  # dynamically consistent inverse
            eye = torch.eye(num_joints, device=jacobian_b.device)
            efforts += ((eye - jac_t @ jbar.transpose(-1, -2)) @ torque[..., None])[..., 0]
        return efforts

    def _task_mass_matrix(self, jacobian: torch.Tensor, mass_inv: torch.Tensor) -> torch.Tensor:
        """Lambda = (J M^-1 J^T)^-1, or its translation and rotation blocks alone (partial)."""
        if not self.cfg.partial_inertial_dynamics_decoupling:
            return inverse_spd(jacobian @ mass_inv @ jacobian.transpose(-1, -2))
        out = torch.zeros(jacobian.shape[0], 6, 6, device=jacobian.device)
        for rows in (slice(0, 3), slice(3, 6)):
            j = jacobian[:, rows]
            out[:, rows, rows] = inverse_spd(j @ mass_inv @ j.transpose(-1, -2))
        return out


def _six(value) -> list[float]:
    values = [float(value)] * 6 if isinstance(value, (int, float)) else [float(v) for v in value]
    if len(values) != 6:
        raise ValueError(f"expected one value or 6 (x, y, z, rx, ry, rz), got {value!r}")
    return values
