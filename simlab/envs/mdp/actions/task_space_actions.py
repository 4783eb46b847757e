"""Task-space action terms: the action is an end-effector target that a controller turns into joint
commands (Isaac Lab's differential-IK and operational-space actions)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils
from simlab.controllers import DifferentialIKController, OperationalSpaceController
from simlab.managers.action_manager import ActionTerm
from simlab.utils.env_mask import env_mask, masked_copy_

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv

    from . import actions_cfg


class _BodyFrameAction(ActionTerm):
    """Shared by the task-space actions: the controlled joints, the end-effector body (plus offset),
    its pose, velocity and Jacobian in the robot's root frame."""

    def __init__(self, cfg, env: ManagerBasedEnv):
        super().__init__(cfg, env)
        asset = self._asset
        if not hasattr(asset, "root_physx_view"):
            raise ValueError(f"{type(cfg).__name__}: asset '{cfg.asset_name}' is not an articulation")
        self._joint_ids, self._joint_names = asset.find_joints(cfg.joint_names)
        self._num_joints = len(self._joint_ids)
        body_ids, body_names = asset.find_bodies(cfg.body_name)
        if len(body_ids) != 1:
            raise ValueError(
                f"{type(cfg).__name__}.body_name {cfg.body_name!r} matches {len(body_ids)} bodies {body_names};"
                f" name one of {asset.body_names}"
            )
        self._body_idx, self._body_name = body_ids[0], body_names[0]
        # PhysX's Jacobians leave out a fixed root; a floating root adds 6 dofs in front.
        if asset.is_fixed_base:
            if self._body_idx == 0:
                raise ValueError(f"{type(cfg).__name__}.body_name {cfg.body_name!r} is the fixed root: it cannot move")
            self._jacobi_body_idx = self._body_idx - 1
            self._jacobi_joint_ids = list(self._joint_ids)
        else:
            self._jacobi_body_idx = self._body_idx
            self._jacobi_joint_ids = [i + 6 for i in self._joint_ids]
        self._jacobi_joint_index = torch.tensor(self._jacobi_joint_ids, dtype=torch.long, device=self.device)
        self._joint_index = torch.tensor(self._joint_ids, dtype=torch.long, device=self.device)
        if cfg.body_offset is not None:
            self._offset_pos = torch.tensor(cfg.body_offset.pos, device=self.device).repeat(self.num_envs, 1)
            self._offset_rot = torch.tensor(cfg.body_offset.rot, device=self.device).repeat(self.num_envs, 1)
        else:
            self._offset_pos = self._offset_rot = None

    @property
    def jacobian_w(self) -> torch.Tensor:
        jac = self._asset.root_physx_view.get_jacobians()[:, self._jacobi_body_idx]
        return jac.index_select(-1, self._jacobi_joint_index)

    @property
    def jacobian_b(self) -> torch.Tensor:
        """(N, 6, num_joints) Jacobian of the end-effector frame (body plus offset), root frame."""
        rot = math_utils.matrix_from_quat(math_utils.quat_inv(self._asset.data.root_quat_w))
        jac = self.jacobian_w
        jac = torch.cat([rot @ jac[:, :3], rot @ jac[:, 3:]], dim=1)
        if self._offset_pos is not None:
            # the offset point moves at v + w x r, r the offset in the root frame
            body_quat_b = math_utils.quat_mul(
                math_utils.quat_inv(self._asset.data.root_quat_w), self._asset.data.body_quat_w[:, self._body_idx]
            )
            r = math_utils.quat_apply(body_quat_b, self._offset_pos)
            jac = torch.cat([jac[:, :3] - math_utils.skew_symmetric_matrix(r) @ jac[:, 3:], jac[:, 3:]], dim=1)
        return jac

    def _ee_pose_b(self) -> tuple[torch.Tensor, torch.Tensor]:
        data = self._asset.data
        # positions from the env origin: the same difference, without the origin's float32 rounding
        body = self._body_idx
        pos_b, quat_b = math_utils.subtract_frame_transforms(
            data.root_pos_env, data.root_quat_w, data.body_pos_env[:, body], data.body_quat_w[:, body]
        )
        if self._offset_pos is not None:
            pos_b, quat_b = math_utils.combine_frame_transforms(pos_b, quat_b, self._offset_pos, self._offset_rot)
        return pos_b, quat_b

    def _ee_vel_b(self) -> torch.Tensor:
        data = self._asset.data
        inv = math_utils.quat_inv(data.root_quat_w)
        lin = data.body_lin_vel_w[:, self._body_idx] - data.root_lin_vel_w
        ang = data.body_ang_vel_w[:, self._body_idx] - data.root_ang_vel_w
        lin, ang = math_utils.quat_apply(inv, lin), math_utils.quat_apply(inv, ang)
        if self._offset_pos is not None:
            body_quat_b = math_utils.quat_mul(inv, data.body_quat_w[:, self._body_idx])
            lin = lin + torch.cross(ang, math_utils.quat_apply(body_quat_b, self._offset_pos), dim=-1)
        return torch.cat([lin, ang], dim=-1)


class DifferentialInverseKinematicsAction(_BodyFrameAction):
    """The action is the IK controller's command (scaled); joint position targets come out."""

    cfg: actions_cfg.DifferentialInverseKinematicsActionCfg

    def __init__(self, cfg: actions_cfg.DifferentialInverseKinematicsActionCfg, env: ManagerBasedEnv):
        super().__init__(cfg, env)
        self._ik_controller = DifferentialIKController(cfg.controller, self.num_envs, self.device)
        dim = self._ik_controller.action_dim
        self._raw_actions = torch.zeros(self.num_envs, dim, device=self.device)
        self._processed_actions = torch.zeros_like(self._raw_actions)
        self._scale = self._per_dim("scale", cfg.scale, dim)
        self._offset = self._per_dim("offset", cfg.offset, dim)
        if cfg.clip is not None:
            raise ValueError(f"{type(cfg).__name__}.clip is not supported for task-space actions; scale the action")

    def _per_dim(self, name: str, value: float | tuple[float, ...], dim: int) -> torch.Tensor:
        values = torch.as_tensor(value, dtype=torch.float32, device=self.device).reshape(-1)
        if values.numel() not in (1, dim):
            raise ValueError(
                f"{type(self.cfg).__name__}.{name} has {values.numel()} values; give one number or {dim}"
                f" (one per command entry: {self._ik_controller._layout()})"
            )
        return values.expand(dim).repeat(self.num_envs, 1)

    @property
    def action_dim(self) -> int:
        return self._ik_controller.action_dim

    @property
    def raw_actions(self) -> torch.Tensor:
        return self._raw_actions

    @property
    def processed_actions(self) -> torch.Tensor:
        return self._processed_actions

    def process_actions(self, actions: torch.Tensor) -> None:
        self._raw_actions[:] = actions
        self._processed_actions[:] = actions * self._scale + self._offset
        pos, quat = self._ee_pose_b()
        self._ik_controller.set_command(self._processed_actions, pos, quat)

    def apply_actions(self) -> None:
        pos, quat = self._ee_pose_b()
        joint_pos = self._asset.data.joint_pos.index_select(1, self._joint_index)
        targets = self._ik_controller.compute(pos, quat, self.jacobian_b, joint_pos)
        self._asset.set_joint_position_target(targets, joint_ids=self._joint_ids)

    def reset(self, env_ids=None) -> None:
        masked_copy_(self._raw_actions, env_mask(env_ids, self.num_envs, self.device), 0.0)


class OperationalSpaceControllerAction(_BodyFrameAction):
    """The action is the operational-space controller's command; joint efforts come out."""

    cfg: actions_cfg.OperationalSpaceControllerActionCfg

    def __init__(self, cfg: actions_cfg.OperationalSpaceControllerActionCfg, env: ManagerBasedEnv):
        super().__init__(cfg, env)
        if cfg.controller_cfg.contact_wrench_stiffness_task is not None:
            raise ValueError(
                f"{type(cfg).__name__}: controller_cfg.contact_wrench_stiffness_task (closed-loop force control)"
                " needs a measured end-effector force, which this action term does not read; leave it None"
                " (wrench targets are then open-loop) or call OperationalSpaceController.compute yourself"
                " with current_ee_force_b"
            )
        self._osc = OperationalSpaceController(cfg.controller_cfg, self.num_envs, self.device)
        dim = self._osc.action_dim
        self._raw_actions = torch.zeros(self.num_envs, dim, device=self.device)
        self._processed_actions = torch.zeros_like(self._raw_actions)
        scale = torch.ones(dim, device=self.device)
        start = 0
        for target in self._osc.target_list:
            if target == "pose_abs":
                scale[start : start + 3] = cfg.position_scale
                start += 7
            elif target == "pose_rel":
                scale[start : start + 3] = cfg.position_scale
                scale[start + 3 : start + 6] = cfg.orientation_scale
                start += 6
            else:
                scale[start : start + 6] = cfg.wrench_scale
                start += 6
        if cfg.controller_cfg.impedance_mode in ("variable_kp", "variable"):
            scale[start : start + 6] = cfg.stiffness_scale
            start += 6
        if cfg.controller_cfg.impedance_mode == "variable":
            scale[start : start + 6] = cfg.damping_ratio_scale
        self._scale = scale
        if cfg.nullspace_joint_pos_target == "none":
            self._nullspace_target = None
        elif cfg.nullspace_joint_pos_target == "center":
            limits = self._asset.data.soft_joint_pos_limits[:, self._joint_ids]
            self._nullspace_target = limits.mean(dim=-1)
        elif cfg.nullspace_joint_pos_target == "default":
            self._nullspace_target = self._asset.data.default_joint_pos[:, self._joint_ids].clone()
        else:
            raise ValueError(
                f"nullspace_joint_pos_target {cfg.nullspace_joint_pos_target!r}: use 'none', 'center' or 'default'"
            )

    @property
    def action_dim(self) -> int:
        return self._osc.action_dim

    @property
    def raw_actions(self) -> torch.Tensor:
        return self._raw_actions

    @property
    def processed_actions(self) -> torch.Tensor:
        return self._processed_actions

    def process_actions(self, actions: torch.Tensor) -> None:
        self._raw_actions[:] = actions
        self._processed_actions[:] = actions * self._scale
        pos, quat = self._ee_pose_b()
        self._osc.set_command(self._processed_actions, current_ee_pose_b=torch.cat([pos, quat], dim=-1))

    def apply_actions(self) -> None:
        view, data = self._asset.root_physx_view, self._asset.data
        pos, quat = self._ee_pose_b()
        ids = self._joint_index
        jac_ids = self._jacobi_joint_index
        mass = view.get_generalized_mass_matrices().index_select(1, jac_ids).index_select(2, jac_ids)
        efforts = self._osc.compute(
            self.jacobian_b,
            current_ee_pose_b=torch.cat([pos, quat], dim=-1),
            current_ee_vel_b=self._ee_vel_b(),
            mass_matrix=mass,
            gravity=view.get_gravity_compensation_forces().index_select(1, jac_ids),
            current_joint_pos=data.joint_pos.index_select(1, ids),
            current_joint_vel=data.joint_vel.index_select(1, ids),
            nullspace_joint_pos_target=self._nullspace_target,
        )
        self._asset.set_joint_effort_target(efforts, joint_ids=self._joint_ids)

    def reset(self, env_ids=None) -> None:
        masked_copy_(self._raw_actions, env_mask(env_ids, self.num_envs, self.device), 0.0)
