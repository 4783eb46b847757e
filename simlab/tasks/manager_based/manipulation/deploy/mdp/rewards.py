"""Keypoint rewards for tracking a commanded pose (Isaac Lab's ``deploy/mdp/rewards.py``).

A pose is compared through keypoints: its origin and the points ``keypoint_scale`` along each of its
axes, both ways (7 points). Their mean distance to the commanded pose's points measures position and
orientation error in metres at once. The hand's pose is read from a frame transformer (its first
target, in its source frame), and the command is taken as given in that same frame.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import SceneEntityCfg
from simlab.utils.math import quat_apply

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

__all__ = ["compute_keypoint_distance", "keypoint_command_error", "keypoint_command_error_exp"]


def _keypoint_offsets(add_center: bool, device) -> torch.Tensor:
    axes = torch.eye(3, device=device)
    offsets = [torch.zeros(1, 3, device=device)] if add_center else []
    return torch.cat([*offsets, axes, -axes])


def compute_keypoint_distance(
    current_pos: torch.Tensor,
    current_quat: torch.Tensor,
    target_pos: torch.Tensor,
    target_quat: torch.Tensor,
    keypoint_scale: float = 1.0,
    add_cube_center_kp: bool = True,
) -> torch.Tensor:
    """Distance of each keypoint of the current pose to its target, ``(num_envs, num_keypoints)``."""
    offsets = _keypoint_offsets(add_cube_center_kp, current_pos.device) * keypoint_scale
    n, k = current_pos.shape[0], offsets.shape[0]
    offsets = offsets.expand(n, k, 3)

    def keypoints(pos: torch.Tensor, quat: torch.Tensor) -> torch.Tensor:
        return quat_apply(quat.unsqueeze(1).expand(n, k, 4), offsets) + pos.unsqueeze(1)

    return torch.linalg.norm(keypoints(target_pos, target_quat) - keypoints(current_pos, current_quat), dim=-1)


def _command_keypoint_distance(
    env: ManagerBasedRLEnv, command_name: str, asset_cfg: SceneEntityCfg, keypoint_scale: float, add_center: bool
) -> torch.Tensor:
    frame = env.scene[asset_cfg.name].data
    command = env.command_manager.get_command(command_name)
    return compute_keypoint_distance(
        frame.target_pos_source[:, 0],
        frame.target_quat_source[:, 0],
        command[:, :3],
        command[:, 3:7],
        keypoint_scale,
        add_center,
    )


def keypoint_command_error(
    env: ManagerBasedRLEnv,
    command_name: str,
    asset_cfg: SceneEntityCfg,
    keypoint_scale: float = 1.0,
    add_cube_center_kp: bool = True,
) -> torch.Tensor:
    """Mean keypoint distance [m] of the frame transformer's first target to the command."""
    return _command_keypoint_distance(env, command_name, asset_cfg, keypoint_scale, add_cube_center_kp).mean(-1)


def keypoint_command_error_exp(
    env: ManagerBasedRLEnv,
    command_name: str,
    asset_cfg: SceneEntityCfg,
    kp_exp_coeffs: list[tuple[float, float]] = [(1.0, 0.1)],  # noqa: B006 - Isaac Lab's signature
    kp_use_sum_of_exps: bool = True,
    keypoint_scale: float = 1.0,
    add_cube_center_kp: bool = True,
) -> torch.Tensor:
    """Sum over ``(a, b)`` of ``1 / (exp(a d) + b + exp(-a d))``: a peak of ``1 / (2 + b)`` at ``d = 0``,
    narrower as ``a`` grows. ``d`` is each keypoint's distance (averaged after, with
    ``kp_use_sum_of_exps``) or their mean distance (before)."""
    distance = _command_keypoint_distance(env, command_name, asset_cfg, keypoint_scale, add_cube_center_kp)
    if not kp_use_sum_of_exps:
        distance = distance.mean(-1, keepdim=True)
    reward = torch.zeros_like(distance[:, 0])
    for a, b in kp_exp_coeffs:
        reward += (1.0 / (torch.exp(a * distance) + b + torch.exp(-a * distance))).mean(-1)
    return reward
