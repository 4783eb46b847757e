"""Reward terms: ``func(env, ...) -> (num_envs,)``. Isaac Lab's names and meanings; the reward
manager multiplies each by its weight and the env step ``dt``."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils
from simlab.managers import SceneEntityCfg
from simlab.managers.manager_base import ManagerTermBase

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

_ROBOT = SceneEntityCfg("robot")


# -- general ---------------------------------------------------------------------------------------


def is_alive(env: ManagerBasedRLEnv) -> torch.Tensor:
    """1 for envs that did not terminate (time-outs count as alive)."""
    return (~env.termination_manager.terminated).float()


def is_terminated(env: ManagerBasedRLEnv) -> torch.Tensor:
    """1 for envs that terminated (not by time-out)."""
    return env.termination_manager.terminated.float()


class is_terminated_term(ManagerTermBase):  # noqa: N801 - Isaac Lab's name
    """1 for envs ended by one of the termination terms ``term_keys`` (names or regexes), except time-outs."""

    def __init__(self, cfg, env: ManagerBasedRLEnv):
        super().__init__(cfg, env)
        keys = cfg.params.get("term_keys", ".*")
        self._term_names = env.termination_manager.find_terms(keys)

    def __call__(self, env: ManagerBasedRLEnv, term_keys: str | list[str] = ".*") -> torch.Tensor:
        tm = env.termination_manager
        hit = torch.zeros(env.num_envs, dtype=torch.bool, device=env.device)
        for name in self._term_names:
            hit |= tm.get_term(name)
        return (hit & ~tm.time_outs).float()


# -- root penalties --------------------------------------------------------------------------------


def lin_vel_z_l2(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    return torch.square(env.scene[asset_cfg.name].data.root_lin_vel_b[:, 2])


def ang_vel_xy_l2(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    return torch.sum(torch.square(env.scene[asset_cfg.name].data.root_ang_vel_b[:, :2]), dim=1)


def flat_orientation_l2(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Squared xy components of the gravity direction in the root frame (0 when upright)."""
    return torch.sum(torch.square(env.scene[asset_cfg.name].data.projected_gravity_b[:, :2]), dim=1)


def base_height_l2(
    env: ManagerBasedRLEnv,
    target_height: float,
    asset_cfg: SceneEntityCfg = _ROBOT,
    sensor_cfg: SceneEntityCfg | None = None,
) -> torch.Tensor:
    """Squared difference of the root height from ``target_height``: above z = 0, or with a height
    scanner ``sensor_cfg``, above the mean height of the ground its rays hit."""
    target = target_height
    if sensor_cfg is not None:
        target = target_height + torch.mean(env.scene.sensors[sensor_cfg.name].data.ray_hits_w[..., 2], dim=1)
    return torch.square(env.scene[asset_cfg.name].data.root_pos_w[:, 2] - target)


# -- joint penalties -------------------------------------------------------------------------------


def joint_torques_l2(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    return torch.sum(torch.square(env.scene[asset_cfg.name].data.applied_torque[:, asset_cfg.joint_ids]), dim=1)


def joint_vel_l1(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg) -> torch.Tensor:
    return torch.sum(torch.abs(env.scene[asset_cfg.name].data.joint_vel[:, asset_cfg.joint_ids]), dim=1)


def joint_vel_l2(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    return torch.sum(torch.square(env.scene[asset_cfg.name].data.joint_vel[:, asset_cfg.joint_ids]), dim=1)


def joint_acc_l2(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    return torch.sum(torch.square(env.scene[asset_cfg.name].data.joint_acc[:, asset_cfg.joint_ids]), dim=1)


def joint_deviation_l1(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Absolute deviation of the joint positions from their defaults."""
    data = env.scene[asset_cfg.name].data
    angle = data.joint_pos[:, asset_cfg.joint_ids] - data.default_joint_pos[:, asset_cfg.joint_ids]
    return torch.sum(torch.abs(angle), dim=1)


def joint_pos_limits(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """How far the joints are beyond their soft position limits (summed)."""
    data = env.scene[asset_cfg.name].data
    pos = data.joint_pos[:, asset_cfg.joint_ids]
    limits = data.soft_joint_pos_limits[:, asset_cfg.joint_ids]
    below = -(pos - limits[..., 0]).clip(max=0.0)
    above = (pos - limits[..., 1]).clip(min=0.0)
    return torch.sum(below + above, dim=1)


def joint_vel_limits(env: ManagerBasedRLEnv, soft_ratio: float, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Joint speed beyond ``soft_ratio`` times the velocity limits, each joint's excess clipped to [0, 1]."""
    data = env.scene[asset_cfg.name].data
    excess = (
        torch.abs(data.joint_vel[:, asset_cfg.joint_ids])
        - data.soft_joint_vel_limits[:, asset_cfg.joint_ids] * soft_ratio
    )
    return torch.sum(excess.clip(min=0.0, max=1.0), dim=1)


def applied_torque_limits(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """How much the actuators clipped the torques they were asked for (summed)."""
    data = env.scene[asset_cfg.name].data
    ids = asset_cfg.joint_ids
    return torch.sum(torch.abs(data.applied_torque[:, ids] - data.computed_torque[:, ids]), dim=1)


# -- action penalties ------------------------------------------------------------------------------


def action_rate_l2(env: ManagerBasedRLEnv) -> torch.Tensor:
    return torch.sum(torch.square(env.action_manager.action - env.action_manager.prev_action), dim=1)


def action_l2(env: ManagerBasedRLEnv) -> torch.Tensor:
    return torch.sum(torch.square(env.action_manager.action), dim=1)


# -- contacts --------------------------------------------------------------------------------------


def _peak_contact_force(env: ManagerBasedRLEnv, sensor_cfg: SceneEntityCfg) -> torch.Tensor:
    """(N, B) the largest contact force magnitude of each selected body over the sensor's history."""
    history = env.scene.sensors[sensor_cfg.name].data.net_forces_w_history
    return torch.max(torch.norm(history[:, :, sensor_cfg.body_ids], dim=-1), dim=1)[0]


def undesired_contacts(env: ManagerBasedRLEnv, threshold: float, sensor_cfg: SceneEntityCfg) -> torch.Tensor:
    """Number of selected bodies touching with more than ``threshold`` newtons."""
    return torch.sum(_peak_contact_force(env, sensor_cfg) > threshold, dim=1).float()


def desired_contacts(env: ManagerBasedRLEnv, sensor_cfg: SceneEntityCfg, threshold: float = 1.0) -> torch.Tensor:
    """1 where none of the selected bodies touches with more than ``threshold`` newtons, else 0."""
    return (_peak_contact_force(env, sensor_cfg) <= threshold).all(dim=1).float()


def contact_forces(env: ManagerBasedRLEnv, threshold: float, sensor_cfg: SceneEntityCfg) -> torch.Tensor:
    """Contact force above ``threshold`` newtons, summed over the selected bodies."""
    return torch.sum((_peak_contact_force(env, sensor_cfg) - threshold).clip(min=0.0), dim=1)


def feet_air_time(
    env: ManagerBasedRLEnv, command_name: str, sensor_cfg: SceneEntityCfg, threshold: float
) -> torch.Tensor:
    """At each touchdown, the flight time just ended minus ``threshold`` seconds, summed over the
    selected feet (long steps earn, short ones cost); 0 while the command's planar speed is below
    0.1 m/s."""
    sensor = env.scene.sensors[sensor_cfg.name]
    first_contact = sensor.compute_first_contact(env.step_dt)[:, sensor_cfg.body_ids]
    last_air_time = sensor.data.last_air_time[:, sensor_cfg.body_ids]
    reward = torch.sum((last_air_time - threshold) * first_contact, dim=1)
    moving = torch.linalg.norm(env.command_manager.get_command(command_name)[:, :2], dim=1) > 0.1
    return reward * moving


def feet_air_time_positive_biped(
    env: ManagerBasedRLEnv, command_name: str, threshold: float, sensor_cfg: SceneEntityCfg
) -> torch.Tensor:
    """For two feet: while exactly one touches, the shorter of the two feet's times in their current
    phase (the stance foot's contact time, the swing foot's air time), capped at ``threshold`` seconds;
    0 in double support or flight, and while the command's planar speed is below 0.1 m/s. It pays for
    alternating single-support steps, up to ``threshold`` long each."""
    data = env.scene.sensors[sensor_cfg.name].data
    air_time = data.current_air_time[:, sensor_cfg.body_ids]
    contact_time = data.current_contact_time[:, sensor_cfg.body_ids]
    in_contact = contact_time > 0.0
    phase_time = torch.where(in_contact, contact_time, air_time)
    single_stance = in_contact.sum(dim=1) == 1
    reward = torch.where(single_stance, phase_time.min(dim=1).values, 0.0).clamp(max=threshold)
    moving = torch.linalg.norm(env.command_manager.get_command(command_name)[:, :2], dim=1) > 0.1
    return reward * moving


def feet_slide(env: ManagerBasedRLEnv, sensor_cfg: SceneEntityCfg, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Planar speed of the selected feet while they touch (more than 1 N in the sensor's
    history), summed. ``asset_cfg`` selects the same feet as bodies of the robot."""
    contacts = _peak_contact_force(env, sensor_cfg) > 1.0
    body_vel = env.scene[asset_cfg.name].data.body_lin_vel_w[:, asset_cfg.body_ids, :2]
    return torch.sum(body_vel.norm(dim=-1) * contacts, dim=1)


# -- velocity tracking -----------------------------------------------------------------------------


def track_lin_vel_xy_exp(
    env: ManagerBasedRLEnv, std: float, command_name: str, asset_cfg: SceneEntityCfg = _ROBOT
) -> torch.Tensor:
    """``exp(-|v_xy_cmd - v_xy|^2 / std^2)`` with the velocities in the root frame."""
    data = env.scene[asset_cfg.name].data
    error = torch.sum(
        torch.square(env.command_manager.get_command(command_name)[:, :2] - data.root_lin_vel_b[:, :2]), dim=1
    )
    return torch.exp(-error / std**2)


def track_ang_vel_z_exp(
    env: ManagerBasedRLEnv, std: float, command_name: str, asset_cfg: SceneEntityCfg = _ROBOT
) -> torch.Tensor:
    """``exp(-(w_z_cmd - w_z)^2 / std^2)`` with the yaw rate in the root frame."""
    data = env.scene[asset_cfg.name].data
    error = torch.square(env.command_manager.get_command(command_name)[:, 2] - data.root_ang_vel_b[:, 2])
    return torch.exp(-error / std**2)


def track_lin_vel_xy_yaw_frame_exp(
    env: ManagerBasedRLEnv, std: float, command_name: str, asset_cfg: SceneEntityCfg = _ROBOT
) -> torch.Tensor:
    """As ``track_lin_vel_xy_exp`` with the velocity in the yaw-aligned (gravity-aligned) root frame."""
    data = env.scene[asset_cfg.name].data
    vel_yaw = math_utils.quat_apply_inverse(math_utils.yaw_quat(data.root_quat_w), data.root_lin_vel_w)
    error = torch.sum(torch.square(env.command_manager.get_command(command_name)[:, :2] - vel_yaw[:, :2]), dim=1)
    return torch.exp(-error / std**2)


def track_ang_vel_z_world_exp(
    env: ManagerBasedRLEnv, command_name: str, std: float, asset_cfg: SceneEntityCfg = _ROBOT
) -> torch.Tensor:
    """As ``track_ang_vel_z_exp`` with the yaw rate in the world frame."""
    error = torch.square(
        env.command_manager.get_command(command_name)[:, 2] - env.scene[asset_cfg.name].data.root_ang_vel_w[:, 2]
    )
    return torch.exp(-error / std**2)


def stand_still_joint_deviation_l1(
    env: ManagerBasedRLEnv, command_name: str, command_threshold: float = 0.06, asset_cfg: SceneEntityCfg = _ROBOT
) -> torch.Tensor:
    """``joint_deviation_l1`` while the commanded planar speed is below ``command_threshold`` [m/s], else 0."""
    command = env.command_manager.get_command(command_name)
    standing = torch.norm(command[:, :2], dim=1) < command_threshold
    return joint_deviation_l1(env, asset_cfg) * standing
