"""Actuator models with Isaac Lab's API: ``compute`` turns joint targets into what the simulation
applies (the torque of an explicit model becomes the ``ctrl`` of its MuJoCo actuators)."""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import TYPE_CHECKING, ClassVar

import torch

from simlab.utils.buffers import DelayBuffer
from simlab.utils.env_mask import env_mask, masked_copy_
from simlab.utils.errors import ConfigError
from simlab.utils.interpolation import LinearInterpolation
from simlab.utils.string import resolve_matching_names_values
from simlab.utils.types import ArticulationActions

if TYPE_CHECKING:
    from .actuator_cfg import ActuatorBaseCfg, DelayedPDActuatorCfg, RemotizedPDActuatorCfg


class ActuatorBase:
    """A group of joints of one articulation driven by the same actuator model (Isaac Lab's API).

    Each gain or limit is the config's value, else the default passed in (what the robot file says;
    Isaac Lab passes the USD values). Tensors are ``(num_envs, num_joints)``. Explicit models turn
    targets into torque with :meth:`compute`, keeping ``computed_effort`` (the model's torque) and
    ``applied_effort`` (after the model's limits). ``effort_limit`` is the model's own limit;
    ``effort_limit_sim`` and ``velocity_limit_sim`` are what the simulation enforces. As in Isaac Lab,
    an explicit model's limits come from its config alone: without ``effort_limit`` it clips at
    ``effort_limit_sim``, itself ``1e9`` when unset (the robot file's limit is for implicit drives).
    """

    is_implicit_model: ClassVar[bool] = False
    _DEFAULT_MAX_EFFORT_SIM: ClassVar[float] = 1.0e9
    """The simulation's effort cap of an explicit model whose config sets no ``effort_limit_sim``."""

    def __init__(
        self,
        cfg: ActuatorBaseCfg,
        joint_names: list[str],
        joint_ids: Sequence[int] | torch.Tensor,
        num_envs: int,
        device: str | torch.device,
        stiffness: torch.Tensor | float = 0.0,
        damping: torch.Tensor | float = 0.0,
        armature: torch.Tensor | float = 0.0,
        friction: torch.Tensor | float = 0.0,
        dynamic_friction: torch.Tensor | float = 0.0,
        viscous_friction: torch.Tensor | float = 0.0,
        effort_limit: torch.Tensor | float = torch.inf,
        velocity_limit: torch.Tensor | float = torch.inf,
    ):
        self.cfg = cfg
        self._joint_names = list(joint_names)
        self.joint_indices = torch.as_tensor(list(joint_ids), dtype=torch.long, device=device)
        self.num_envs = num_envs
        self.device = device
        self.stiffness = self._parse_joint_parameter(cfg.stiffness, stiffness)
        self.damping = self._parse_joint_parameter(cfg.damping, damping)
        self.armature = self._parse_joint_parameter(cfg.armature, armature)
        self.friction = self._parse_joint_parameter(cfg.friction, friction)
        self.dynamic_friction = self._parse_joint_parameter(getattr(cfg, "dynamic_friction", None), dynamic_friction)
        self.viscous_friction = self._parse_joint_parameter(getattr(cfg, "viscous_friction", None), viscous_friction)
        if self.is_implicit_model:  # the simulation is the model: one effort limit
            sim_effort = cfg.effort_limit_sim if cfg.effort_limit_sim is not None else cfg.effort_limit
            self.effort_limit_sim = self._parse_joint_parameter(sim_effort, effort_limit)
            self.effort_limit = self.effort_limit_sim
        else:
            self.effort_limit_sim = self._parse_joint_parameter(cfg.effort_limit_sim, self._DEFAULT_MAX_EFFORT_SIM)
            self.effort_limit = self._parse_joint_parameter(cfg.effort_limit, self.effort_limit_sim)
        # ``velocity_limit`` is the model's own (a DC motor's no-load speed), else the simulation's cap.
        self.velocity_limit_sim = self._parse_joint_parameter(cfg.velocity_limit_sim, velocity_limit)
        model_velocity = cfg.velocity_limit if cfg.velocity_limit is not None else cfg.velocity_limit_sim
        self.velocity_limit = self._parse_joint_parameter(model_velocity, velocity_limit)
        self.computed_effort = torch.zeros(num_envs, self.num_joints, device=device)
        self.applied_effort = torch.zeros_like(self.computed_effort)

    def __str__(self) -> str:
        kind = "implicit" if self.is_implicit_model else "explicit"
        return (
            f"<class {type(self).__name__}> object:\n\tModel type            : {kind}\n"
            f"\tNumber of joints      : {self.num_joints}\n\tJoint names expression: {self.cfg.joint_names_expr}\n"
            f"\tJoint names           : {self.joint_names}\n\tJoint indices         : {self.joint_indices.tolist()}\n"
        )

    @property
    def num_joints(self) -> int:
        return len(self._joint_names)

    @property
    def joint_names(self) -> list[str]:
        return self._joint_names

    def reset(self, env_ids) -> None:
        """Stateless models have nothing to reset."""

    def restart(self, mask: torch.Tensor) -> None:
        """The physics restarted the worlds in ``mask`` (their state blew up): zero the efforts computed
        from that state there (and, in models with memory, forget it), so that readers (``applied_torque``,
        ``computed_torque`` rewards) see finite values until the env's reset of those worlds in the same
        step. Draws nothing (the reset draws: a draw here, every step, would shift every later one)."""
        masked_copy_(self.computed_effort, mask, 0.0)
        masked_copy_(self.applied_effort, mask, 0.0)

    def compute(
        self, control_action: ArticulationActions, joint_pos: torch.Tensor, joint_vel: torch.Tensor
    ) -> ArticulationActions:
        """Turn the joint targets of this group into what the simulation receives."""
        raise NotImplementedError(f"{type(self).__name__} does not compute actions")

    def _pd_effort(self, control_action: ArticulationActions, joint_pos: torch.Tensor, joint_vel: torch.Tensor):
        """``kp (q* - q) + kd (qd* - qd) + tau_ff`` into ``computed_effort``, clipped into ``applied_effort``
        (in place, so that a captured CUDA graph keeps reading the same buffers)."""
        # written with out= and in-place ops: each op is a kernel launch on the GPU, every physics step
        position_error = control_action.joint_positions - joint_pos
        velocity_error = control_action.joint_velocities - joint_vel
        if control_action.joint_efforts is not None:  # tau_ff + kp e, one fused multiply-add
            effort = torch.addcmul(
                control_action.joint_efforts, self.stiffness, position_error, out=self.computed_effort
            )
        else:
            effort = torch.mul(self.stiffness, position_error, out=self.computed_effort)
        effort.addcmul_(self.damping, velocity_error)
        self._clip_effort(effort, out=self.applied_effort)

    @property
    def effort_limit(self) -> torch.Tensor:
        return self._effort_limit

    @effort_limit.setter
    def effort_limit(self, value: torch.Tensor) -> None:
        # its negative kept beside it: the clip then takes one kernel, not two (every physics step);
        # assign a new limit (``act.effort_limit = ...``) rather than writing into it
        self._effort_limit = value
        self._neg_effort_limit = -value

    def _clip_effort(self, effort: torch.Tensor, out: torch.Tensor | None = None) -> torch.Tensor:
        """``effort`` within the model's limits (written into ``out`` when given)."""
        return torch.clamp(effort, min=self._neg_effort_limit, max=self._effort_limit, out=out)

    def _parse_joint_parameter(self, cfg_value, default) -> torch.Tensor:
        """The config's value (a float, or a dict of joint-name patterns to floats), else ``default``
        (a float or a ``(num_envs, num_joints)`` tensor), as a ``(num_envs, num_joints)`` tensor."""
        shape = (self.num_envs, self.num_joints)
        if isinstance(default, torch.Tensor):
            out = default.to(self.device, torch.float32).expand(shape).clone()
        else:
            out = torch.full(shape, float(default), device=self.device)
        if cfg_value is None:
            return out
        if isinstance(cfg_value, (int, float)):
            return torch.full(shape, float(cfg_value), device=self.device)
        if isinstance(cfg_value, dict):
            ids, _, values = resolve_matching_names_values(cfg_value, self.joint_names)
            out[:, ids] = torch.tensor(values, dtype=torch.float32, device=self.device)
            return out
        raise TypeError(
            f"{type(self).__name__} for {self.joint_names}: a gain or limit is a float or a dict of joint-name"
            f" patterns to floats, got {type(cfg_value).__name__}."
        )


class ImplicitActuator(ActuatorBase):
    """The PD law runs inside MuJoCo (bias terms of the actuator); see ``actuator_cfg``.

    :meth:`compute` leaves the targets as they are (MuJoCo applies them) and records the torque the
    PD law asks for and its value within the effort limit, as Isaac Lab's implicit actuator does.
    """

    is_implicit_model: ClassVar[bool] = True

    def __init__(self, cfg, joint_names, joint_ids, num_envs, device, **defaults):
        check_implicit_velocity_limit(cfg, joint_names)
        check_implicit_effort_limit(cfg, joint_names)
        # One limit each, under both names, as Isaac Lab's implicit actuator keeps its (copied) config;
        # a lone ``velocity_limit`` is ignored (check_implicit_velocity_limit said so).
        cfg = cfg.replace()
        cfg.effort_limit = cfg.effort_limit_sim = _first_set(cfg.effort_limit_sim, cfg.effort_limit)
        cfg.velocity_limit = cfg.velocity_limit_sim
        super().__init__(cfg, joint_names, joint_ids, num_envs, device, **defaults)

    def compute(self, control_action, joint_pos, joint_vel):
        self._pd_effort(control_action, joint_pos, joint_vel)
        return control_action


class IdealPDActuator(ActuatorBase):
    """``tau = kp (q* - q) + kd (qd* - qd) + tau_ff``, clipped to ``effort_limit``, in torch."""

    def compute(self, control_action, joint_pos, joint_vel):
        self._pd_effort(control_action, joint_pos, joint_vel)
        return ArticulationActions(joint_efforts=self.applied_effort, joint_indices=control_action.joint_indices)


class DCMotor(IdealPDActuator):
    """The torque available shrinks linearly with speed: ``tau_max(qd) = tau_sat (1 - qd / qd_max)``,
    and never exceeds ``effort_limit`` (Isaac Lab's four-quadrant DC motor). Past the corner speed,
    where a line reaches the other side's effort limit, the motor brakes at that limit."""

    def __init__(self, cfg, joint_names, joint_ids, num_envs, device, **defaults):
        super().__init__(cfg, joint_names, joint_ids, num_envs, device, **defaults)
        self._saturation_effort = float(cfg.saturation_effort)
        if not torch.isfinite(self.velocity_limit).all():
            raise ValueError(f"DCMotorCfg for {joint_names} needs a finite velocity_limit (the no-load speed)")
        self._joint_vel = torch.zeros_like(self.computed_effort)
        """The joint velocities of the last ``compute``, clipped to the corner speed: where the
        torque-speed lines are read (kept in the clip's one kernel, not copied first)."""
        self._vel_at_effort_lim = self.velocity_limit * (1 + self.effort_limit / self._saturation_effort)
        """The corner speed: where the torque-speed line meets the effort limit of the other sign."""
        # made once, so that the clip takes four kernels after the speed's (it runs every physics step):
        # the corner speed's negative and the two lines' torques at zero speed
        self._neg_vel_at_effort_lim = -self._vel_at_effort_lim
        self._saturation_pair = torch.tensor([1.0, -1.0], device=device) * self._saturation_effort

    def restart(self, mask: torch.Tensor) -> None:
        super().restart(mask)
        masked_copy_(self._joint_vel, mask, 0.0)

    def compute(self, control_action, joint_pos, joint_vel):
        self._record_speed(joint_vel)
        return super().compute(control_action, joint_pos, joint_vel)

    def _record_speed(self, joint_vel: torch.Tensor) -> None:
        """Keep where the torque-speed lines are read: ``joint_vel`` clipped to the corner speed."""
        torch.clamp(joint_vel, min=self._neg_vel_at_effort_lim, max=self._vel_at_effort_lim, out=self._joint_vel)

    def _clip_effort(self, effort: torch.Tensor, out: torch.Tensor | None = None) -> torch.Tensor:
        # The torque-speed lines bound the torque in all four quadrants: beyond the no-load speed the
        # motor can only brake. Read at a speed clipped to the corner speed, both bounds meet at the
        # braking side's effort limit there and beyond.
        # Both lines, +-tau_sat - tau_sat qd / qd_max, in one (N, J, 2) kernel, then both within the
        # effort limits (below the corner speed the upper line never falls under -limit, nor the lower
        # one over +limit, so this is the minimum with +limit and the maximum with -limit).
        speed_ratio = self._joint_vel / self.velocity_limit
        bounds = torch.add(self._saturation_pair, speed_ratio.unsqueeze(-1), alpha=-self._saturation_effort)
        bounds.clamp_(min=self._neg_effort_limit.unsqueeze(-1), max=self.effort_limit.unsqueeze(-1))
        return torch.clamp(effort, min=bounds[..., 1], max=bounds[..., 0], out=out)


class DelayedPDActuator(IdealPDActuator):
    """An ideal PD whose commands arrive ``d`` physics steps late: the torque at step ``k`` is the PD
    law on the targets sent at step ``k - d`` and the joint state of step ``k`` (Isaac Lab's model).

    ``d`` is drawn per env, uniformly in ``[min_delay, max_delay]``, at construction and at every
    reset of that env; after a reset an env gets its oldest command since the reset until it has
    ``d`` of them, never one from before. One delay buffer (``targets_delay_buffer``: positions,
    velocities and efforts stacked, where Isaac Lab has three buffers sharing their lags) keeps its
    state on the device and resets by mask, so the model runs inside a graphed step.
    """

    cfg: DelayedPDActuatorCfg

    def __init__(self, cfg, joint_names, joint_ids, num_envs, device, **defaults):
        super().__init__(cfg, joint_names, joint_ids, num_envs, device, **defaults)
        low, high = cfg.min_delay, cfg.max_delay
        if not all(type(v) is int and v >= 0 for v in (low, high)) or low > high:
            raise ConfigError(
                f"{type(cfg).__name__} for {joint_names}: min_delay={low!r} and max_delay={high!r} must be"
                " integers (physics steps) with 0 <= min_delay <= max_delay."
            )
        # One buffer for the three target kinds, each frame (positions, velocities, efforts) side by side:
        # they share the lags, and one buffer costs a third of the kernels of three (this runs every
        # physics step); the buffer joins the three in the kernel that shifts its history.
        self.targets_delay_buffer = DelayBuffer(high, num_envs, device=device)
        self._no_effort = torch.zeros_like(self.computed_effort)
        self.reset(None)

    # Isaac Lab's three buffer names, kept for code that reads or sets the lags through them (e.g.
    # ``act.positions_delay_buffer.time_lags``): all three are the one stacked buffer, so a lag set
    # through any of them applies to positions, velocities and efforts alike.
    @property
    def positions_delay_buffer(self) -> DelayBuffer:
        return self.targets_delay_buffer

    @property
    def velocities_delay_buffer(self) -> DelayBuffer:
        return self.targets_delay_buffer

    @property
    def efforts_delay_buffer(self) -> DelayBuffer:
        return self.targets_delay_buffer

    def reset(self, env_ids) -> None:
        mask = env_mask(env_ids, self.num_envs, self.device)
        # a lag drawn for every env, kept where the mask is set: no host read, fixed shapes
        lags = torch.randint(
            self.cfg.min_delay, self.cfg.max_delay + 1, (self.num_envs,), dtype=torch.int, device=self.device
        )
        self.targets_delay_buffer.set_time_lag(lags, batch_mask=mask)
        self.targets_delay_buffer.reset(batch_mask=mask)

    def restart(self, mask: torch.Tensor) -> None:
        super().restart(mask)
        self.targets_delay_buffer.reset(batch_mask=mask)  # forgets the targets, keeps the lags (no draw)

    def compute(self, control_action, joint_pos, joint_vel):
        efforts = control_action.joint_efforts if control_action.joint_efforts is not None else self._no_effort
        targets = (control_action.joint_positions, control_action.joint_velocities, efforts)
        delayed = self.targets_delay_buffer.compute(targets)  # (num_envs, 3 num_joints)
        positions, velocities, efforts = delayed.view(self.num_envs, 3, self.num_joints).unbind(1)
        delayed = ArticulationActions(
            joint_positions=positions,
            joint_velocities=velocities,
            joint_efforts=efforts,
            joint_indices=control_action.joint_indices,
        )
        return super().compute(delayed, joint_pos, joint_vel)


class RemotizedPDActuator(DelayedPDActuator):
    """A delayed PD whose torque limit depends on the joint angle: joints driven through a linkage,
    whose transmission ratio, and so the torque the motor can produce at the joint, varies with angle.

    ``joint_parameter_lookup`` rows are ``(angle [rad], transmission ratio, max torque [N m])`` with
    ascending angles; the limit at the current joint angle is interpolated linearly between rows and
    held at the end rows' values outside them (Isaac Lab's model: one table for the whole group, the
    ratio column kept for reference). The model has no other effort or velocity limit.
    """

    cfg: RemotizedPDActuatorCfg

    def __init__(self, cfg, joint_names, joint_ids, num_envs, device, **defaults):
        # as in Isaac Lab: the table is the only limit (on a copy: the user's config is left alone)
        cfg = cfg.replace(effort_limit=torch.inf, velocity_limit=torch.inf)
        super().__init__(cfg, joint_names, joint_ids, num_envs, device, **defaults)
        table = torch.as_tensor(cfg.joint_parameter_lookup, dtype=torch.float32)
        if table.dim() != 2 or table.shape[1] != 3 or table.shape[0] < 1 or torch.any(table[1:, 0] < table[:-1, 0]):
            raise ConfigError(
                f"RemotizedPDActuatorCfg for {joint_names}: joint_parameter_lookup must be rows of (angle,"
                f" transmission ratio, max torque) with ascending angles, got shape {tuple(table.shape)}."
            )
        self._joint_parameter_lookup = table.to(device)
        # the limit and its negative interpolated together: the clip then needs no negation
        limits = torch.stack((self.max_torque_samples, -self.max_torque_samples), dim=1)
        self._torque_limits = LinearInterpolation(self.angle_samples, limits, device=device)

    @property
    def angle_samples(self) -> torch.Tensor:
        return self._joint_parameter_lookup[:, 0]

    @property
    def transmission_ratio_samples(self) -> torch.Tensor:
        return self._joint_parameter_lookup[:, 1]

    @property
    def max_torque_samples(self) -> torch.Tensor:
        return self._joint_parameter_lookup[:, 2]

    def compute(self, control_action, joint_pos, joint_vel):
        # the table is the only limit: the PD's one clip reads it (no clip at an infinite limit first)
        self._limits = self._torque_limits.compute(joint_pos)  # (num_envs, num_joints, 2): max, -max
        return super().compute(control_action, joint_pos, joint_vel)

    def _clip_effort(self, effort: torch.Tensor, out: torch.Tensor | None = None) -> torch.Tensor:
        return torch.clamp(effort, min=self._limits[..., 1], max=self._limits[..., 0], out=out)


def _first_set(*values):
    return next((v for v in values if v is not None), None)


def check_implicit_effort_limit(cfg: ActuatorBaseCfg, joint_names: list[str]) -> None:
    """An implicit drive has one effort limit: both names set to different values is refused."""
    if cfg.effort_limit is not None and cfg.effort_limit_sim is not None and cfg.effort_limit != cfg.effort_limit_sim:
        raise ValueError(
            f"ImplicitActuatorCfg for {joint_names} sets effort_limit={cfg.effort_limit} and"
            f" effort_limit_sim={cfg.effort_limit_sim}: an implicit drive has one limit, set only 'effort_limit_sim'."
        )


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
