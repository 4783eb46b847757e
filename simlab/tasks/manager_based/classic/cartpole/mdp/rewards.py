"""Rewards specific to the cartpole."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import SceneEntityCfg
from simlab.utils.math import wrap_to_pi

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

__all__ = ["joint_pos_target_l2"]


def joint_pos_target_l2(env: ManagerBasedRLEnv, target: float, asset_cfg: SceneEntityCfg) -> torch.Tensor:
    """Squared distance of the joint angles (wrapped to [-pi, pi)) from ``target``, summed."""
    joint_pos = wrap_to_pi(env.scene[asset_cfg.name].data.joint_pos[:, asset_cfg.joint_ids])
    return torch.sum(torch.square(joint_pos - target), dim=1)
