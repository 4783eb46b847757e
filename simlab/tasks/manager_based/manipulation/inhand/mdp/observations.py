"""Observation terms of the in-hand task."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import SceneEntityCfg
from simlab.utils import math as math_utils

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

__all__ = ["goal_quat_diff"]


def goal_quat_diff(
    env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg, command_name: str, make_quat_unique: bool
) -> torch.Tensor:
    """The rotation from the goal orientation to the object's, (w, x, y, z) (real part >= 0 if unique)."""
    goal_quat_w = env.command_manager.get_term(command_name).command[:, 3:7]
    quat = math_utils.quat_mul(env.scene[asset_cfg.name].data.root_quat_w, math_utils.quat_conjugate(goal_quat_w))
    return math_utils.quat_unique(quat) if make_quat_unique else quat
