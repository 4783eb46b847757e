"""Rewards of the classic locomotion tasks: run towards a far target, upright, with little effort.

The stateful terms are :class:`ManagerTermBase` classes whose per-env buffers reset by mask
(``simlab.utils.env_mask``), so the step can replay as a CUDA graph.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils
from simlab.managers import RewardTermCfg, SceneEntityCfg
from simlab.managers.manager_base import ManagerTermBase
from simlab.utils.env_mask import PerEnvState, env_mask
from simlab.utils.string import resolve_matching_names_values

from .observations import base_heading_proj, base_up_proj, to_target_w

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

__all__ = [
    "joint_pos_limits_penalty_ratio",
    "move_to_target_bonus",
    "power_consumption",
    "progress_reward",
    "upright_posture_bonus",
]

_ROBOT = SceneEntityCfg("robot")


def upright_posture_bonus(env: ManagerBasedRLEnv, threshold: float, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """1 where the base's up axis is within ``acos(threshold)`` of the world's up axis, else 0."""
    return (base_up_proj(env, asset_cfg).squeeze(-1) > threshold).float()


def move_to_target_bonus(
    env: ManagerBasedRLEnv, threshold: float, target_pos: tuple[float, float, float], asset_cfg: SceneEntityCfg = _ROBOT
) -> torch.Tensor:
    """1 when heading to the target within ``acos(threshold)``, else the heading cosine / threshold."""
    heading_proj = base_heading_proj(env, target_pos, asset_cfg).squeeze(-1)
    return torch.where(heading_proj > threshold, 1.0, heading_proj / threshold)


class progress_reward(ManagerTermBase):  # noqa: N801 - Isaac Lab's name
    """Horizontal distance to the target covered in this step, per second of step (potential difference).

    The potential of an env that resets is set to its new distance, so its first step rewards only
    that step's progress. (Isaac Lab measures the reset potential in 3D and later ones in the plane;
    here both are horizontal, so a reset's height does not count as progress.)
    """

    def __init__(self, cfg: RewardTermCfg, env: ManagerBasedRLEnv):
        super().__init__(cfg, env)
        self.state = PerEnvState(env.num_envs, env.device)
        self.potentials = self.state.zeros("potentials", reset=self._potentials_now)
        self.prev_potentials = self.state.zeros("prev_potentials", reset=self._potentials_now)

    def _potentials_now(self) -> torch.Tensor:
        """Minus the horizontal distance to the target, per step ``dt``, for every env."""
        asset_cfg = self.cfg.params.get("asset_cfg", _ROBOT)
        to_target = to_target_w(self._env, self.cfg.params["target_pos"], asset_cfg)
        return -torch.norm(to_target[:, :2], dim=-1) / self._env.step_dt

    def reset(self, env_ids: torch.Tensor | None = None) -> None:
        self.state.reset(env_mask(env_ids, self.num_envs, self.device))

    def __call__(
        self, env: ManagerBasedRLEnv, target_pos: tuple[float, float, float], asset_cfg: SceneEntityCfg = _ROBOT
    ) -> torch.Tensor:
        self.prev_potentials.copy_(self.potentials)
        self.potentials.copy_(self._potentials_now())
        return self.potentials - self.prev_potentials


class _GearWeightedTerm(ManagerTermBase):
    """A term weighting each joint by its gear ratio relative to the largest (``gear_ratio``: regex -> gear)."""

    def __init__(self, cfg: RewardTermCfg, env: ManagerBasedRLEnv):
        super().__init__(cfg, env)
        asset = env.scene[cfg.params.get("asset_cfg", _ROBOT).name]
        ids, _, gears = resolve_matching_names_values(cfg.params["gear_ratio"], asset.joint_names)
        gear_ratio = torch.ones(asset.num_joints, device=env.device)  # joints no key matches count 1
        gear_ratio[ids] = torch.tensor(gears, dtype=torch.float32, device=env.device)
        self.gear_ratio_scaled = gear_ratio / gear_ratio.max()


class joint_pos_limits_penalty_ratio(_GearWeightedTerm):  # noqa: N801 - Isaac Lab's name
    """How far joints go past ``threshold`` of their soft range (normalised to [-1, 1]), gear-weighted, summed."""

    def __call__(
        self, env: ManagerBasedRLEnv, threshold: float, gear_ratio: dict[str, float], asset_cfg: SceneEntityCfg = _ROBOT
    ) -> torch.Tensor:
        data = env.scene[asset_cfg.name].data
        limits = data.soft_joint_pos_limits
        joint_pos_scaled = math_utils.scale_transform(data.joint_pos, limits[..., 0], limits[..., 1]).abs()
        violation = (joint_pos_scaled - threshold) / (1.0 - threshold) * self.gear_ratio_scaled
        return torch.sum((joint_pos_scaled > threshold) * violation, dim=-1)


class power_consumption(_GearWeightedTerm):  # noqa: N801 - Isaac Lab's name
    """Sum of |action x joint velocity|, gear-weighted (the actions are joint torques)."""

    def __call__(
        self, env: ManagerBasedRLEnv, gear_ratio: dict[str, float], asset_cfg: SceneEntityCfg = _ROBOT
    ) -> torch.Tensor:
        joint_vel = env.scene[asset_cfg.name].data.joint_vel
        return torch.sum(torch.abs(env.action_manager.action * joint_vel * self.gear_ratio_scaled), dim=-1)
