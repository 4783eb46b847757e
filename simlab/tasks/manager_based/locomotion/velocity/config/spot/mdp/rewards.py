"""Spot's velocity-task rewards (Isaac Lab's ``config/spot/mdp/rewards.py``: the same names, parameters
and formulas). Tracking uses exp(-|error| / std) kernels; the gait terms read the contact sensor's
current and last air/contact times of the feet."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import torch

from simlab.managers import ManagerTermBase, SceneEntityCfg

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv
    from simlab.managers import RewardTermCfg

__all__ = [
    "GaitReward",
    "action_smoothness_penalty",
    "air_time_reward",
    "air_time_variance_penalty",
    "base_angular_velocity_reward",
    "base_linear_velocity_reward",
    "base_motion_penalty",
    "base_orientation_penalty",
    "foot_clearance_reward",
    "foot_slip_penalty",
    "joint_acceleration_penalty",
    "joint_position_penalty",
    "joint_torques_penalty",
    "joint_velocity_penalty",
]


def _per_step(env: ManagerBasedRLEnv, key: tuple, compute: Callable[[], torch.Tensor]) -> torch.Tensor:
    """``compute()`` once per reward computation (``RewardManager.shared``): several terms read it."""
    manager = getattr(env, "reward_manager", None)
    return compute() if manager is None else manager.shared(key, compute)


def _moving(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg, velocity_threshold: float) -> torch.Tensor:
    """Envs asked to move (any nonzero command) or moving faster than ``velocity_threshold`` in the plane."""

    def moving() -> torch.Tensor:
        command = torch.linalg.norm(env.command_manager.get_command("base_velocity"), dim=1)
        speed = torch.linalg.norm(env.scene[asset_cfg.name].data.root_lin_vel_b[:, :2], dim=1)
        return (command > 0.0) | (speed > velocity_threshold)

    return _per_step(env, ("spot_moving", asset_cfg.name, velocity_threshold), moving)


def _planar_speed(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg) -> torch.Tensor:
    """(envs, bodies) world-frame xy speed of ``asset_cfg``'s bodies (the feet: clearance and slip)."""

    def speed() -> torch.Tensor:
        velocity = env.scene[asset_cfg.name].data.body_lin_vel_w[:, asset_cfg.body_ids, :2]
        return torch.linalg.norm(velocity, dim=2)

    ids = asset_cfg.body_ids
    return _per_step(
        env, ("spot_planar_speed", asset_cfg.name, repr(ids) if isinstance(ids, slice) else tuple(ids)), speed
    )


def _air_time_sensor(env: ManagerBasedRLEnv, sensor_cfg: SceneEntityCfg):
    sensor = env.scene.sensors[sensor_cfg.name]
    if not sensor.cfg.track_air_time:
        raise RuntimeError(f"{sensor_cfg.name}: the Spot gait rewards need ContactSensorCfg(track_air_time=True)")
    return sensor


# -- task rewards -----------------------------------------------------------------------------------


def air_time_reward(
    env: ManagerBasedRLEnv,
    asset_cfg: SceneEntityCfg,
    sensor_cfg: SceneEntityCfg,
    mode_time: float,
    velocity_threshold: float,
) -> torch.Tensor:
    """Moving: each foot earns its current air or contact time up to ``mode_time`` (nothing once a phase
    lasts longer). Standing still: contact time minus air time, clipped to +-``mode_time``."""
    data = _air_time_sensor(env, sensor_cfg).data
    air = data.current_air_time[:, sensor_cfg.body_ids]
    contact = data.current_contact_time[:, sensor_cfg.body_ids]
    longest = torch.maximum(air, contact)
    stepping = torch.where(longest < mode_time, longest, 0.0)  # Isaac Lab's clamp(max=mode_time) keeps it as is
    standing = (contact - air).clamp(-mode_time, mode_time)
    moving = _moving(env, asset_cfg, velocity_threshold).unsqueeze(1)
    return torch.where(moving, stepping, standing).sum(dim=1)


def base_angular_velocity_reward(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg, std: float) -> torch.Tensor:
    """exp(-|yaw-rate error| / std)."""
    target = env.command_manager.get_command("base_velocity")[:, 2]
    error = (target - env.scene[asset_cfg.name].data.root_ang_vel_b[:, 2]).abs()
    return torch.exp(-error / std)


def base_linear_velocity_reward(
    env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg, std: float, ramp_at_vel: float = 1.0, ramp_rate: float = 0.5
) -> torch.Tensor:
    """exp(-|planar velocity error| / std), scaled up by ``1 + ramp_rate (|command| - ramp_at_vel)`` for
    commands faster than ``ramp_at_vel`` (fast commands are worth more)."""
    target = env.command_manager.get_command("base_velocity")[:, :2]
    error = torch.linalg.norm(target - env.scene[asset_cfg.name].data.root_lin_vel_b[:, :2], dim=1)
    scale = (1.0 + ramp_rate * (torch.linalg.norm(target, dim=1) - ramp_at_vel)).clamp(min=1.0)
    return torch.exp(-error / std) * scale


class GaitReward(ManagerTermBase):
    """A trot (or any gait of two synchronised foot pairs): the feet of a pair share their air and contact
    times, and each foot of one pair is in the air while each of the other pair stands. The reward is the
    product of exp(-squared time differences / std) over the two synced pairs and the four cross pairs,
    each squared difference capped at ``max_err``^2; zero for envs neither commanded nor moving."""

    def __init__(self, cfg: RewardTermCfg, env: ManagerBasedRLEnv):
        super().__init__(cfg, env)
        pairs = cfg.params["synced_feet_pair_names"]
        if len(pairs) != 2 or any(len(pair) != 2 for pair in pairs):
            raise ValueError(
                f"GaitReward: synced_feet_pair_names must be two pairs of foot bodies (a trot), got {pairs!r}"
            )
        self.sensor = _air_time_sensor(env, cfg.params["sensor_cfg"])
        (a0, a1), (b0, b1) = ([self.sensor.find_bodies(name)[0][0] for name in pair] for pair in pairs)
        self.synced = [(a0, a1), (b0, b1)]
        self.opposed = [(a0, b0), (a1, b1), (a0, b1), (b0, a1)]
        # The six pairs' two time differences each, x = t_i - t_j and y = t_i' - t_j', as one gather from
        # the air and contact times side by side (air time of body k in column k, contact time in
        # column B + k): indices (side i/j, pair, x/y); all pairs then take a few kernels together.
        num_bodies = self.sensor.data.current_air_time.shape[1]
        air, contact = (lambda k: k), (lambda k: num_bodies + k)
        same = [((air(i), contact(i)), (air(j), contact(j))) for i, j in self.synced]
        opposite = [((air(i), contact(i)), (contact(j), air(j))) for i, j in self.opposed]
        sides = [[left for left, _ in same + opposite], [right for _, right in same + opposite]]
        self._pair_columns = torch.tensor(sides, dtype=torch.long, device=env.device)  # (2, 6, 2)
        self._times = torch.zeros(env.num_envs, 2, num_bodies, device=env.device)

    def __call__(
        self,
        env: ManagerBasedRLEnv,
        std: float,
        max_err: float,
        velocity_threshold: float,
        synced_feet_pair_names,
        asset_cfg: SceneEntityCfg,
        sensor_cfg: SceneEntityCfg,
    ) -> torch.Tensor:
        # same phase (synced pairs): equal air times and equal contact times; opposite phase (the other
        # four): one's air time is the other's contact time. Each pair: exp(-(min(x^2, e^2) + min(y^2, e^2)) / std)
        data = self.sensor.data
        times = torch.stack((data.current_air_time, data.current_contact_time), dim=1, out=self._times)
        sides = times.view(env.num_envs, -1)[:, self._pair_columns]  # (N, 2, 6, 2)
        squared = torch.square(sides[:, 0] - sides[:, 1]).clamp_(max=max_err**2)
        reward = torch.exp(-squared.sum(dim=2) / std).prod(dim=1)
        return torch.where(_moving(env, asset_cfg, velocity_threshold), reward, 0.0)


def foot_clearance_reward(
    env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg, target_height: float, std: float, tanh_mult: float
) -> torch.Tensor:
    """exp(-sum over feet of (foot height - target)^2 tanh(tanh_mult |foot planar speed|) / std): swinging
    feet should pass at ``target_height`` (world z)."""
    data = env.scene[asset_cfg.name].data
    height_error = torch.square(data.body_pos_w[:, asset_cfg.body_ids, 2] - target_height)
    swing = torch.tanh(tanh_mult * _planar_speed(env, asset_cfg))
    return torch.exp(-(height_error * swing).sum(dim=1) / std)


# -- penalties --------------------------------------------------------------------------------------


def action_smoothness_penalty(env: ManagerBasedRLEnv) -> torch.Tensor:
    """|action - previous action| (the norm, not its square)."""
    return torch.linalg.norm(env.action_manager.action - env.action_manager.prev_action, dim=1)


def air_time_variance_penalty(env: ManagerBasedRLEnv, sensor_cfg: SceneEntityCfg) -> torch.Tensor:
    """Variance across the feet of the last air times plus that of the last contact times (each capped at
    0.5 s): the feet should take turns evenly."""
    data = _air_time_sensor(env, sensor_cfg).data
    air = data.last_air_time[:, sensor_cfg.body_ids].clamp(max=0.5)
    contact = data.last_contact_time[:, sensor_cfg.body_ids].clamp(max=0.5)
    return torch.var(air, dim=1) + torch.var(contact, dim=1)


def base_motion_penalty(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg) -> torch.Tensor:
    """0.8 v_z^2 + 0.2 (|roll rate| + |pitch rate|), in the base frame."""
    data = env.scene[asset_cfg.name].data
    return 0.8 * torch.square(data.root_lin_vel_b[:, 2]) + 0.2 * data.root_ang_vel_b[:, :2].abs().sum(dim=1)


def base_orientation_penalty(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg) -> torch.Tensor:
    """|planar part of gravity in the base frame|: zero when level."""
    return torch.linalg.norm(env.scene[asset_cfg.name].data.projected_gravity_b[:, :2], dim=1)


def foot_slip_penalty(
    env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg, sensor_cfg: SceneEntityCfg, threshold: float
) -> torch.Tensor:
    """Sum of the planar speeds of the feet pressing on something (more than ``threshold`` newtons in the
    sensor's history)."""
    history = env.scene.sensors[sensor_cfg.name].data.net_forces_w_history[:, :, sensor_cfg.body_ids]
    in_contact = torch.linalg.norm(history, dim=-1).amax(dim=1) > threshold
    return (in_contact * _planar_speed(env, asset_cfg)).sum(dim=1)


def joint_acceleration_penalty(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg) -> torch.Tensor:
    """|joint accelerations| (the norm over all joints, as Isaac Lab's: ``asset_cfg``'s joints are not read)."""
    return torch.linalg.norm(env.scene[asset_cfg.name].data.joint_acc, dim=1)


def joint_position_penalty(
    env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg, stand_still_scale: float, velocity_threshold: float
) -> torch.Tensor:
    """|joint positions - defaults|, ``stand_still_scale`` times that when neither commanded nor moving."""
    data = env.scene[asset_cfg.name].data
    error = torch.linalg.norm(data.joint_pos - data.default_joint_pos, dim=1)
    return torch.where(_moving(env, asset_cfg, velocity_threshold), error, stand_still_scale * error)


def joint_torques_penalty(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg) -> torch.Tensor:
    """|applied joint torques| (all joints)."""
    return torch.linalg.norm(env.scene[asset_cfg.name].data.applied_torque, dim=1)


def joint_velocity_penalty(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg) -> torch.Tensor:
    """|joint velocities| (all joints, as Isaac Lab's)."""
    return torch.linalg.norm(env.scene[asset_cfg.name].data.joint_vel, dim=1)
