"""Spot's reset event (Isaac Lab's ``spot_mdp.reset_joints_around_default``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import SceneEntityCfg
from simlab.utils.env_mask import is_mask, takes_env_mask
from simlab.utils.math import sample_uniform

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv

__all__ = ["reset_joints_around_default"]

_ROBOT = SceneEntityCfg("robot")


@takes_env_mask
def reset_joints_around_default(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor,
    position_range: tuple[float, float],
    velocity_range: tuple[float, float],
    asset_cfg: SceneEntityCfg = _ROBOT,
) -> None:
    """Joint positions and velocities drawn uniformly from default + ``position_range`` / ``velocity_range``,
    the bounds first clamped to the soft joint position and velocity limits."""
    asset = env.scene[asset_cfg.name]
    data = asset.data
    # a bool mask (inside the env step): draw for every env, write where it is set (fixed shapes)
    rows = slice(None) if is_mask(env_ids) else env_ids
    pos_limits = data.soft_joint_pos_limits[rows]
    vel_limits = data.soft_joint_vel_limits[rows]
    default_pos, default_vel = data.default_joint_pos[rows], data.default_joint_vel[rows]

    def bounds(default, offsets, low, high):
        return (default + offsets[0]).clamp(low, high), (default + offsets[1]).clamp(low, high)

    pos_low, pos_high = bounds(default_pos, position_range, pos_limits[..., 0], pos_limits[..., 1])
    vel_low, vel_high = bounds(default_vel, velocity_range, -vel_limits, vel_limits)
    joint_pos = sample_uniform(pos_low, pos_high, pos_low.shape, pos_low.device)
    joint_vel = sample_uniform(vel_low, vel_high, vel_low.shape, vel_low.device)
    asset.write_joint_state_to_sim(joint_pos, joint_vel, env_ids=env_ids)
