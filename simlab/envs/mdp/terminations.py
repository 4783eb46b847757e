"""Termination terms: ``func(env, ...) -> (num_envs,)`` bool. Isaac Lab's names and meanings."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import SceneEntityCfg

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

_ROBOT = SceneEntityCfg("robot")


def time_out(env: ManagerBasedRLEnv) -> torch.Tensor:
    """The episode reached ``max_episode_length`` env steps."""
    return env.episode_length_buf >= env.max_episode_length


def command_resample(env: ManagerBasedRLEnv, command_name: str, num_resamples: int = 1) -> torch.Tensor:
    """The ``num_resamples``-th command of ``command_name`` since the reset (the reset draws the first)
    runs out within this step: episodes of that many commands."""
    command = env.command_manager.get_term(command_name)
    return (command.time_left <= env.step_dt) & (command.command_counter == num_resamples)


def bad_orientation(env: ManagerBasedRLEnv, limit_angle: float, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """The root tilted more than ``limit_angle`` radians from upright."""
    gravity_b = env.scene[asset_cfg.name].data.projected_gravity_b
    return torch.acos(-gravity_b[:, 2].clamp(-1.0, 1.0)).abs() > limit_angle


def root_height_below_minimum(
    env: ManagerBasedRLEnv, minimum_height: float, asset_cfg: SceneEntityCfg = _ROBOT
) -> torch.Tensor:
    return env.scene[asset_cfg.name].data.root_pos_w[:, 2] < minimum_height


def joint_pos_out_of_limit(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """A joint is outside its soft position limits."""
    data = env.scene[asset_cfg.name].data
    pos = data.joint_pos[:, asset_cfg.joint_ids]
    limits = data.soft_joint_pos_limits[:, asset_cfg.joint_ids]
    return torch.any((pos < limits[..., 0]) | (pos > limits[..., 1]), dim=1)


def joint_pos_out_of_manual_limit(
    env: ManagerBasedRLEnv, bounds: tuple[float, float], asset_cfg: SceneEntityCfg = _ROBOT
) -> torch.Tensor:
    """A joint is outside ``bounds = (lower, upper)``."""
    pos = env.scene[asset_cfg.name].data.joint_pos[:, asset_cfg.joint_ids]
    return torch.any(pos < bounds[0], dim=1) | torch.any(pos > bounds[1], dim=1)


def joint_vel_out_of_limit(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    data = env.scene[asset_cfg.name].data
    ids = asset_cfg.joint_ids
    return torch.any(torch.abs(data.joint_vel[:, ids]) > data.soft_joint_vel_limits[:, ids], dim=1)


def joint_vel_out_of_manual_limit(
    env: ManagerBasedRLEnv, max_velocity: float, asset_cfg: SceneEntityCfg = _ROBOT
) -> torch.Tensor:
    return torch.any(torch.abs(env.scene[asset_cfg.name].data.joint_vel[:, asset_cfg.joint_ids]) > max_velocity, dim=1)


def joint_effort_out_of_limit(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """The actuators were asked for more effort than their limit (so they clipped it)."""
    data = env.scene[asset_cfg.name].data
    ids = asset_cfg.joint_ids
    return torch.any(torch.abs(data.computed_torque[:, ids]) > data.joint_effort_limits[:, ids], dim=1)


def illegal_contact(env: ManagerBasedRLEnv, threshold: float, sensor_cfg: SceneEntityCfg) -> torch.Tensor:
    """A selected body touched with more than ``threshold`` newtons during the sensor's history."""
    history = env.scene.sensors[sensor_cfg.name].data.net_forces_w_history
    return torch.any(torch.max(torch.norm(history[:, :, sensor_cfg.body_ids], dim=-1), dim=1)[0] > threshold, dim=1)


def terrain_out_of_bounds(
    env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg = _ROBOT, distance_buffer: float = 3.0
) -> torch.Tensor:
    """The root came within ``distance_buffer`` metres of the generated terrain's edge (its tiles and
    border, centred on the origin). Never on a plane, which has no edge."""
    terrain = env.scene.cfg.terrain
    if terrain.terrain_type == "plane":
        return torch.zeros(env.num_envs, dtype=torch.bool, device=env.device)
    if terrain.terrain_type != "generator":
        raise ValueError(
            f"terrain_out_of_bounds: terrain_type {terrain.terrain_type!r} has no known extent; "
            "allowed: 'plane' or 'generator'"
        )
    generator = terrain.terrain_generator
    half_x = 0.5 * (generator.num_rows * generator.size[0] + 2 * generator.border_width) - distance_buffer
    half_y = 0.5 * (generator.num_cols * generator.size[1] + 2 * generator.border_width) - distance_buffer
    position = env.scene[asset_cfg.name].data.root_pos_w
    return (position[:, 0].abs() > half_x) | (position[:, 1].abs() > half_y)
