"""Rewards for opening a drawer: reach the handle, align the gripper, grasp around it, pull.

They read the frame transformers ``ee_frame`` (tool centre point, left fingertip, right fingertip)
and ``cabinet_frame`` (the handle, its x axis out of the drawer front). "Graspable" means the left
fingertip is above the handle and the right one below it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import SceneEntityCfg
from simlab.utils.math import matrix_from_quat

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

__all__ = [
    "align_ee_handle",
    "align_grasp_around_handle",
    "approach_ee_handle",
    "approach_gripper_handle",
    "grasp_handle",
    "multi_stage_open_drawer",
    "open_drawer_bonus",
]


def _tcp_and_handle(env: ManagerBasedRLEnv) -> tuple[torch.Tensor, torch.Tensor]:
    return env.scene["ee_frame"].data.target_pos_w[..., 0, :], env.scene["cabinet_frame"].data.target_pos_w[..., 0, :]


def _is_graspable(env: ManagerBasedRLEnv) -> torch.Tensor:
    """(num_envs,) bool: the left fingertip above the handle and the right one below."""
    handle = env.scene["cabinet_frame"].data.target_pos_w[..., 0, :]
    fingertips = env.scene["ee_frame"].data.target_pos_w[..., 1:, :]
    return (fingertips[:, 1, 2] < handle[:, 2]) & (fingertips[:, 0, 2] > handle[:, 2])


def approach_ee_handle(env: ManagerBasedRLEnv, threshold: float) -> torch.Tensor:
    """``(1 / (1 + d^2))^2`` of the tool centre point's distance ``d`` to the handle, doubled within ``threshold``."""
    tcp, handle = _tcp_and_handle(env)
    distance = torch.linalg.norm(handle - tcp, dim=-1, ord=2)
    reward = (1.0 / (1.0 + distance**2)) ** 2
    return torch.where(distance <= threshold, 2 * reward, reward)


def align_ee_handle(env: ManagerBasedRLEnv) -> torch.Tensor:
    """``0.5 (sign(a) a^2 + sign(b) b^2)`` with ``a`` the gripper's z along the handle's -x (into the
    drawer) and ``b`` the gripper's x along the handle's -y."""
    ee_rot = matrix_from_quat(env.scene["ee_frame"].data.target_quat_w[..., 0, :])
    handle_rot = matrix_from_quat(env.scene["cabinet_frame"].data.target_quat_w[..., 0, :])
    align_z = (ee_rot[..., 2] * -handle_rot[..., 0]).sum(dim=-1)
    align_x = (ee_rot[..., 0] * -handle_rot[..., 1]).sum(dim=-1)
    return 0.5 * (torch.sign(align_z) * align_z**2 + torch.sign(align_x) * align_x**2)


def align_grasp_around_handle(env: ManagerBasedRLEnv) -> torch.Tensor:
    """1 where the fingers straddle the handle (left above, right below), else 0."""
    return _is_graspable(env).float()


def approach_gripper_handle(env: ManagerBasedRLEnv, offset: float = 0.04) -> torch.Tensor:
    """Where the fingers straddle the handle: ``2 offset`` minus the fingertips' heights from it."""
    handle = env.scene["cabinet_frame"].data.target_pos_w[..., 0, :]
    fingertips = env.scene["ee_frame"].data.target_pos_w[..., 1:, :]
    lfinger_dist = torch.abs(fingertips[:, 0, 2] - handle[:, 2])
    rfinger_dist = torch.abs(fingertips[:, 1, 2] - handle[:, 2])
    return _is_graspable(env) * ((offset - lfinger_dist) + (offset - rfinger_dist))


def grasp_handle(
    env: ManagerBasedRLEnv, threshold: float, open_joint_pos: float, asset_cfg: SceneEntityCfg
) -> torch.Tensor:
    """Within ``threshold`` of the handle: how far the finger joints closed from ``open_joint_pos``
    (zero joint position is closed)."""
    tcp, handle = _tcp_and_handle(env)
    gripper_joint_pos = env.scene[asset_cfg.name].data.joint_pos[:, asset_cfg.joint_ids]
    is_close = torch.linalg.norm(handle - tcp, dim=-1, ord=2) <= threshold
    return is_close * torch.sum(open_joint_pos - gripper_joint_pos, dim=-1)


def open_drawer_bonus(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg) -> torch.Tensor:
    """The drawer's opening, doubled while the fingers straddle the handle."""
    drawer_pos = env.scene[asset_cfg.name].data.joint_pos[:, asset_cfg.joint_ids[0]]
    return (_is_graspable(env).float() + 1.0) * drawer_pos


def multi_stage_open_drawer(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg) -> torch.Tensor:
    """0.5 past 1 cm of opening; 1 more past 20 cm and past 30 cm while the fingers straddle the handle."""
    drawer_pos = env.scene[asset_cfg.name].data.joint_pos[:, asset_cfg.joint_ids[0]]
    graspable = _is_graspable(env).float()
    open_easy = (drawer_pos > 0.01) * 0.5
    open_medium = (drawer_pos > 0.2) * graspable
    open_hard = (drawer_pos > 0.3) * graspable
    return open_easy + open_medium + open_hard
