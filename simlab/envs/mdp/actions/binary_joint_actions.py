"""Binary joint actions: one number per env opens or closes a gripper (negative closes)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers.action_manager import ActionTerm
from simlab.utils.env_mask import env_mask, masked_copy_
from simlab.utils.string import resolve_matching_names_values

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv

    from . import actions_cfg


class BinaryJointAction(ActionTerm):
    """Action < 0 commands ``close_command_expr``, otherwise ``open_command_expr`` (Isaac Lab's rule)."""

    cfg: actions_cfg.BinaryJointActionCfg

    def __init__(self, cfg: actions_cfg.BinaryJointActionCfg, env: ManagerBasedEnv):
        super().__init__(cfg, env)
        if not hasattr(self._asset, "find_joints") or self._asset.num_joints == 0:
            raise ValueError(
                f"{type(cfg).__name__}: asset '{cfg.asset_name}' has no joints to open or close (a gripper needs"
                " its finger joints)"
            )
        try:
            self._joint_ids, self._joint_names = self._asset.find_joints(cfg.joint_names)
        except ValueError as err:
            raise ValueError(
                f"{type(cfg).__name__}.joint_names {cfg.joint_names!r} match no finger joint of '{cfg.asset_name}':"
                f" {err}"
            ) from err
        if cfg.clip is not None:
            raise ValueError(f"{type(cfg).__name__}.clip does not apply to a binary action; leave it None")
        self._open = self._command_of(cfg.open_command_expr, "open_command_expr")
        self._close = self._command_of(cfg.close_command_expr, "close_command_expr")
        n, dev = self.num_envs, self.device
        self._raw_actions = torch.zeros(n, 1, device=dev)
        self._processed_actions = self._open.expand(n, -1).clone()

    def _command_of(self, expr: dict[str, float], what: str) -> torch.Tensor:
        ids, names, values = resolve_matching_names_values(expr, self._joint_names)
        if len(ids) != len(self._joint_names):
            missing = sorted(set(self._joint_names) - set(names))
            raise ValueError(
                f"{type(self.cfg).__name__}.{what} {expr!r} gives no value for the joints {missing}; give every joint"
                f" of {self._joint_names} a target"
            )
        command = torch.zeros(len(self._joint_names), device=self.device)
        command[ids] = torch.tensor(values, dtype=torch.float32, device=self.device)
        return command[None]

    @property
    def action_dim(self) -> int:
        return 1

    @property
    def raw_actions(self) -> torch.Tensor:
        return self._raw_actions

    @property
    def processed_actions(self) -> torch.Tensor:
        return self._processed_actions

    def process_actions(self, actions: torch.Tensor) -> None:
        self._raw_actions[:] = actions
        close = actions < 0 if actions.is_floating_point() else actions == 0
        self._processed_actions[:] = torch.where(close, self._close, self._open)

    def reset(self, env_ids=None) -> None:
        masked_copy_(self._raw_actions, env_mask(env_ids, self.num_envs, self.device), 0.0)


class BinaryJointPositionAction(BinaryJointAction):
    """The open or close command as joint position targets."""

    def apply_actions(self) -> None:
        self._asset.set_joint_position_target(self._processed_actions, joint_ids=self._joint_ids)


class BinaryJointVelocityAction(BinaryJointAction):
    """The open or close command as joint velocity targets."""

    def apply_actions(self) -> None:
        self._asset.set_joint_velocity_target(self._processed_actions, joint_ids=self._joint_ids)
