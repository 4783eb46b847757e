"""Actuator models. ``compute`` turns joint targets into the ``ctrl`` of the MuJoCo actuators."""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import TYPE_CHECKING

import torch

from simlab.utils.errors import ConfigError
from simlab.utils.string import resolve_matching_names_values

if TYPE_CHECKING:
    from .actuator_cfg import ActuatorBaseCfg


class ActuatorBase:
    """A group of joints of one articulation driven by the same actuator model."""

    is_implicit_model: bool = False

    def __init__(
        self,
        cfg: ActuatorBaseCfg,
        joint_names: list[str],
        joint_ids: Sequence[int],
        num_envs: int,
        device: str | torch.device,
    ):
        self.cfg = cfg
        self.joint_names = joint_names
        self.joint_indices = torch.as_tensor(list(joint_ids), dtype=torch.long, device=device)
        self.num_envs = num_envs
        self.device = device
        self.num_joints = len(joint_names)
        effort = cfg.effort_limit_sim if cfg.effort_limit_sim is not None else cfg.effort_limit
        self.stiffness = self._per_joint(cfg.stiffness, 0.0)
        self.damping = self._per_joint(cfg.damping, 0.0)
        self.effort_limit = self._per_joint(effort, float("inf"))
        # As in Isaac Lab: ``velocity_limit_sim`` caps the joint speed in the simulation (see
        # ``Articulation.write_data_to_sim``); ``velocity_limit`` is the motor model's own (a DC motor's
        # no-load speed), falling back to the sim limit when unset.
        self.velocity_limit_sim = self._per_joint(cfg.velocity_limit_sim, float("inf"))
        model_velocity = cfg.velocity_limit if cfg.velocity_limit is not None else cfg.velocity_limit_sim
        self.velocity_limit = self._per_joint(model_velocity, float("inf"))
        self.armature = self._per_joint(cfg.armature, 0.0)
        self.friction = self._per_joint(cfg.friction, 0.0)

    def _per_joint(self, value, default: float) -> torch.Tensor:
        values = per_joint_values(value, self.joint_names, default)
        return torch.tensor(values, dtype=torch.float32, device=self.device).repeat(self.num_envs, 1)

    def reset(self, env_ids) -> None:
        """Stateless models have nothing to reset."""

    def compute_torque(
        self,
        pos_target,
        vel_target,
        effort_target,
        joint_pos,
        joint_vel,
        stiffness,
        damping,
        effort_limit,
        velocity_limit,
    ) -> torch.Tensor:
        """The joint torque an explicit model applies (gains and limits are per env and joint)."""
        raise NotImplementedError(f"{type(self).__name__} is computed by the physics engine")


class ImplicitActuator(ActuatorBase):
    """The PD law runs inside MuJoCo (bias terms of the actuator); see ``actuator_cfg``."""

    is_implicit_model = True

    def __init__(self, cfg, joint_names, joint_ids, num_envs, device):
        check_implicit_velocity_limit(cfg, joint_names)
        super().__init__(cfg, joint_names, joint_ids, num_envs, device)


class IdealPDActuator(ActuatorBase):
    """``tau = kp (q* - q) + kd (qd* - qd) + tau_ff``, clipped to the effort limit, in torch."""

    def compute_torque(
        self,
        pos_target,
        vel_target,
        effort_target,
        joint_pos,
        joint_vel,
        stiffness,
        damping,
        effort_limit,
        velocity_limit,
    ):
        torque = stiffness * (pos_target - joint_pos) + damping * (vel_target - joint_vel) + effort_target
        return self._clip_effort(torque, joint_vel, effort_limit, velocity_limit)

    def _clip_effort(self, effort, joint_vel, effort_limit, velocity_limit):
        return torch.clamp(effort, -effort_limit, effort_limit)


class DCMotor(IdealPDActuator):
    """The torque available shrinks linearly with speed: ``tau_max(qd) = tau_sat (1 - qd / qd_max)``."""

    def __init__(self, cfg, joint_names, joint_ids, num_envs, device):
        super().__init__(cfg, joint_names, joint_ids, num_envs, device)
        self.saturation_effort = float(cfg.saturation_effort)
        if not torch.isfinite(self.velocity_limit).all():
            raise ValueError(f"DCMotorCfg for {joint_names} needs a finite velocity_limit")

    def _clip_effort(self, effort, joint_vel, effort_limit, velocity_limit):
        speed_ratio = joint_vel / velocity_limit
        max_effort = torch.minimum(torch.clamp(self.saturation_effort * (1.0 - speed_ratio), min=0.0), effort_limit)
        min_effort = torch.maximum(torch.clamp(self.saturation_effort * (-1.0 - speed_ratio), max=0.0), -effort_limit)
        return torch.clamp(effort, min_effort, max_effort)


def check_implicit_velocity_limit(cfg: ActuatorBaseCfg, joint_names: list[str]) -> None:
    """Isaac Lab's rule for implicit drives: only ``velocity_limit_sim`` limits the simulation.

    A ``velocity_limit`` alone was never applied by Isaac Lab's implicit actuators, which keep
    ignoring it (with a warning) so that old configs simulate as before; simlab does the same and
    says so. Both set to different values is refused.
    """
    if cfg.velocity_limit is None:
        return
    if cfg.velocity_limit_sim is None:
        warnings.warn(
            f"ImplicitActuatorCfg for {joint_names}: 'velocity_limit' does not limit an implicit drive (as in"
            " Isaac Lab); set 'velocity_limit_sim' to cap the joint speed in the simulation.",
            UserWarning,
            stacklevel=3,
        )
    elif cfg.velocity_limit != cfg.velocity_limit_sim:
        raise ConfigError(
            f"ImplicitActuatorCfg for {joint_names} sets velocity_limit={cfg.velocity_limit} and"
            f" velocity_limit_sim={cfg.velocity_limit_sim}: an implicit drive has one limit, set only"
            " 'velocity_limit_sim'."
        )


def per_joint_values(value, joint_names: list[str], default):
    """A float, or a dict of joint-name patterns to floats, as one value per joint."""
    if value is None:
        return [default] * len(joint_names)
    if isinstance(value, (int, float)):
        return [float(value)] * len(joint_names)
    out = [default] * len(joint_names)
    ids, _, values = resolve_matching_names_values(value, joint_names)
    for i, v in zip(ids, values):
        out[i] = float(v)
    return out
