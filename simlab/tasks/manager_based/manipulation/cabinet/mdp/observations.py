"""Observations of the end-effector and the drawer handle, read from the two frame transformers
(``ee_frame``: the tool centre point, then the left and right fingertips; ``cabinet_frame``: the handle)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

__all__ = ["ee_pos", "ee_quat", "fingertips_pos", "rel_ee_drawer_distance"]


def rel_ee_drawer_distance(env: ManagerBasedRLEnv) -> torch.Tensor:
    """(num_envs, 3) from the tool centre point to the drawer handle, world frame."""
    ee_tcp = env.scene["ee_frame"].data.target_pos_w[..., 0, :]
    handle = env.scene["cabinet_frame"].data.target_pos_w[..., 0, :]
    return handle - ee_tcp


def fingertips_pos(env: ManagerBasedRLEnv) -> torch.Tensor:
    """(num_envs, 6) the two fingertips' positions relative to the env origin."""
    fingertips = env.scene["ee_frame"].data.target_pos_w[..., 1:, :] - env.scene.env_origins.unsqueeze(1)
    return fingertips.reshape(env.num_envs, -1)


def ee_pos(env: ManagerBasedRLEnv) -> torch.Tensor:
    """(num_envs, 3) the tool centre point relative to the env origin."""
    return env.scene["ee_frame"].data.target_pos_w[..., 0, :] - env.scene.env_origins


def ee_quat(env: ManagerBasedRLEnv, make_quat_unique: bool = True) -> torch.Tensor:
    """(num_envs, 4) the tool centre point's orientation (w, x, y, z), w >= 0 unless told otherwise."""
    quat = env.scene["ee_frame"].data.target_quat_w[..., 0, :]
    return math_utils.quat_unique(quat) if make_quat_unique else quat
