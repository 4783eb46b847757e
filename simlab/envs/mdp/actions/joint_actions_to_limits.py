"""Joint position actions spread over the joints' limits (Isaac Lab's ``joint_actions_to_limits``).

``JointPositionToLimitsAction``: the scaled action (clipped per joint if ``clip`` is set) becomes a
position target; with ``rescale_to_limits`` it is clipped to [-1, 1] and mapped onto each joint's
soft limits (-1 the lower, +1 the upper). ``EMAJointPositionToLimitsAction`` smooths the targets:
``target = alpha * new + (1 - alpha) * previous target``, clamped to the soft limits; a reset starts
the average from the joints' positions.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.utils.env_mask import env_mask, masked_copy_
from simlab.utils.math import unscale_transform
from simlab.utils.string import resolve_matching_names_values

from .joint_actions import JointAction

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv

    from . import actions_cfg


class JointPositionToLimitsAction(JointAction):
    """Position targets from actions in [-1, 1] over the joints' soft limits (see the module docstring)."""

    cfg: actions_cfg.JointPositionToLimitsActionCfg

    def __init__(self, cfg: actions_cfg.JointPositionToLimitsActionCfg, env: ManagerBasedEnv):
        if cfg.offset != 0.0:
            raise ValueError(
                f"{type(cfg).__name__}: offset must be 0 (the targets span the joint limits), got {cfg.offset!r}"
            )
        super().__init__(cfg, env)

    def _limits(self) -> tuple[torch.Tensor, torch.Tensor]:
        limits = self._asset.data.soft_joint_pos_limits[:, self._joint_ids]
        return limits[..., 0], limits[..., 1]

    def process_actions(self, actions: torch.Tensor) -> None:
        super().process_actions(actions)  # raw * scale, clipped per joint
        if self.cfg.rescale_to_limits:
            lower, upper = self._limits()
            self._processed_actions.copy_(unscale_transform(self._processed_actions.clamp(-1.0, 1.0), lower, upper))

    def apply_actions(self) -> None:
        self._asset.set_joint_position_target(self.processed_actions, joint_ids=self._joint_ids)


class EMAJointPositionToLimitsAction(JointPositionToLimitsAction):
    """The targets of :class:`JointPositionToLimitsAction` as an exponential moving average."""

    cfg: actions_cfg.EMAJointPositionToLimitsActionCfg

    def __init__(self, cfg: actions_cfg.EMAJointPositionToLimitsActionCfg, env: ManagerBasedEnv):
        super().__init__(cfg, env)
        if isinstance(cfg.alpha, (int, float)):
            if not 0.0 <= cfg.alpha <= 1.0:
                raise ValueError(f"EMA action: alpha must be in [0, 1], got {cfg.alpha}")
            self._alpha: torch.Tensor | float = float(cfg.alpha)
        elif isinstance(cfg.alpha, dict):
            self._alpha = torch.ones(self.num_envs, self.action_dim, device=self.device)
            idx, names, values = resolve_matching_names_values(cfg.alpha, self._joint_names)
            bad = [f"{n}: {v}" for n, v in zip(names, values) if not 0.0 <= v <= 1.0]
            if bad:
                raise ValueError(f"EMA action: alpha must be in [0, 1] for every joint, got {', '.join(bad)}")
            self._alpha[:, idx] = torch.tensor(values, dtype=torch.float32, device=self.device)
        else:
            raise ValueError(f"EMA action: alpha must be a float or a dict of joint-name patterns, got {cfg.alpha!r}")
        self._prev_applied_actions = torch.zeros_like(self._processed_actions)

    def process_actions(self, actions: torch.Tensor) -> None:
        super().process_actions(actions)
        lower, upper = self._limits()
        ema = self._alpha * self._processed_actions + (1.0 - self._alpha) * self._prev_applied_actions
        self._processed_actions.copy_(torch.clamp(ema, lower, upper))
        self._prev_applied_actions.copy_(self._processed_actions)

    def reset(self, env_ids=None) -> None:
        super().reset(env_ids)
        mask = env_mask(env_ids, self.num_envs, self.device)
        masked_copy_(self._prev_applied_actions, mask, self._asset.data.joint_pos[:, self._joint_ids])
