"""Joint action terms: the action, scaled and offset, becomes joint efforts, position or velocity targets."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers.action_manager import ActionTerm
from simlab.utils.env_mask import env_mask, masked_copy_
from simlab.utils.string import resolve_matching_names_values

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv

    from . import actions_cfg


class JointAction(ActionTerm):
    """``processed = raw * scale + offset``, clipped if ``clip`` is set."""

    cfg: actions_cfg.JointActionCfg

    def __init__(self, cfg: actions_cfg.JointActionCfg, env: ManagerBasedEnv):
        super().__init__(cfg, env)
        if not hasattr(self._asset, "find_joints"):
            raise ValueError(f"asset '{cfg.asset_name}' ({type(self._asset).__name__}) has no joints to act on")
        ids, names = self._asset.find_joints(cfg.joint_names, preserve_order=cfg.preserve_order)
        self._joint_names = names
        self._num_joints = len(ids)
        # All joints in model order: a slice writes without a gather.
        self._joint_ids = slice(None) if ids == list(range(self._asset.num_joints)) else ids
        n, dev = self.num_envs, self.device
        self._raw_actions = torch.zeros(n, self.action_dim, device=dev)
        self._processed_actions = torch.zeros_like(self._raw_actions)
        self._scale = self._per_joint(cfg.scale, "scale", 1.0)
        self._offset = self._per_joint(cfg.offset, "offset", 0.0)
        self._clip = None
        if cfg.clip is not None:
            if not isinstance(cfg.clip, dict):
                raise ValueError(f"clip must be a dict of joint-name patterns to (min, max), got {cfg.clip!r}")
            self._clip = torch.tensor([[-float("inf"), float("inf")]], device=dev).repeat(n, self.action_dim, 1)
            idx, _, values = resolve_matching_names_values(cfg.clip, self._joint_names)
            self._clip[:, idx] = torch.tensor(values, dtype=torch.float32, device=dev)

    def _per_joint(self, value, what: str, default: float) -> torch.Tensor | float:
        if isinstance(value, (int, float)):
            return float(value)
        if isinstance(value, dict):
            out = torch.full((self.num_envs, self.action_dim), default, device=self.device)
            idx, _, values = resolve_matching_names_values(value, self._joint_names)
            out[:, idx] = torch.tensor(values, dtype=torch.float32, device=self.device)
            return out
        raise ValueError(f"{what} must be a float or a dict of joint-name patterns to floats, got {value!r}")

    @property
    def action_dim(self) -> int:
        return self._num_joints

    @property
    def raw_actions(self) -> torch.Tensor:
        return self._raw_actions

    @property
    def processed_actions(self) -> torch.Tensor:
        return self._processed_actions

    @property
    def joint_names(self) -> list[str]:
        return self._joint_names

    def process_actions(self, actions: torch.Tensor) -> None:
        self._raw_actions[:] = actions
        torch.add(actions * self._scale, self._offset, out=self._processed_actions)
        if self._clip is not None:
            self._processed_actions.clamp_(min=self._clip[..., 0], max=self._clip[..., 1])

    def reset(self, env_ids=None) -> None:
        masked_copy_(self._raw_actions, env_mask(env_ids, self.num_envs, self.device), 0.0)


class JointPositionAction(JointAction):
    """Absolute joint position targets (offset by the default joint positions if ``use_default_offset``)."""

    def __init__(self, cfg: actions_cfg.JointPositionActionCfg, env: ManagerBasedEnv):
        super().__init__(cfg, env)
        if cfg.use_default_offset:
            self._offset = self._asset.data.default_joint_pos[:, self._joint_ids].clone()

    def apply_actions(self) -> None:
        self._asset.set_joint_position_target(self.processed_actions, joint_ids=self._joint_ids)


class RelativeJointPositionAction(JointAction):
    """Joint position targets relative to the current joint positions."""

    def __init__(self, cfg: actions_cfg.RelativeJointPositionActionCfg, env: ManagerBasedEnv):
        super().__init__(cfg, env)
        if cfg.use_zero_offset:
            self._offset = 0.0

    def apply_actions(self) -> None:
        current = self._asset.data.joint_pos[:, self._joint_ids]
        self._asset.set_joint_position_target(current + self.processed_actions, joint_ids=self._joint_ids)


class JointVelocityAction(JointAction):
    """Joint velocity targets (offset by the default joint velocities if ``use_default_offset``)."""

    def __init__(self, cfg: actions_cfg.JointVelocityActionCfg, env: ManagerBasedEnv):
        super().__init__(cfg, env)
        if cfg.use_default_offset:
            self._offset = self._asset.data.default_joint_vel[:, self._joint_ids].clone()

    def apply_actions(self) -> None:
        self._asset.set_joint_velocity_target(self.processed_actions, joint_ids=self._joint_ids)


class JointEffortAction(JointAction):
    """Joint efforts (forces/torques), sent as feed-forward efforts to the joints' actuators."""

    def apply_actions(self) -> None:
        self._asset.set_joint_effort_target(self.processed_actions, joint_ids=self._joint_ids)
