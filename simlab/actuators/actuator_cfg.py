"""Actuator configurations: which joints a group drives and with which gains and limits.

Every actuated joint gets one MuJoCo ``general`` actuator with unit gain. For an *implicit*
actuator the model also carries the PD terms as bias, ``force = ctrl - kp * q - kd * qd``, and the
articulation writes ``ctrl = kp * q_target + kd * qd_target + effort_target``: MuJoCo then applies
``kp (q* - q) + kd (qd* - qd) + tau_ff``, clipped to the effort limit, and ``implicitfast``
integrates the damping implicitly, as PhysX drives do. For an *explicit* actuator (ideal PD, DC
motor) the bias is zero and ``ctrl`` is the torque computed in torch.
"""

from __future__ import annotations

from dataclasses import MISSING

from simlab.utils import configclass

from .actuator_pd import DCMotor, IdealPDActuator, ImplicitActuator


@configclass
class ActuatorBaseCfg:
    class_type: type = MISSING
    joint_names_expr: list[str] = MISSING
    """Joint names or regular expressions (full match) of the joints this group drives."""
    effort_limit: dict[str, float] | float | None = None
    velocity_limit: dict[str, float] | float | None = None
    effort_limit_sim: dict[str, float] | float | None = None
    velocity_limit_sim: dict[str, float] | float | None = None
    stiffness: dict[str, float] | float | None = MISSING
    """PD position gain [N/m or N m/rad]; None means 0."""
    damping: dict[str, float] | float | None = MISSING
    """PD velocity gain [N s/m or N m s/rad]; None means 0."""
    armature: dict[str, float] | float | None = None
    friction: dict[str, float] | float | None = None


@configclass
class ImplicitActuatorCfg(ActuatorBaseCfg):
    """PD drive computed by the physics engine (a MuJoCo actuator with PD bias terms)."""

    class_type: type = ImplicitActuator


@configclass
class IdealPDActuatorCfg(ActuatorBaseCfg):
    """PD torque computed in torch every physics step, clipped to the effort limit."""

    class_type: type = IdealPDActuator


@configclass
class DCMotorCfg(IdealPDActuatorCfg):
    """Ideal PD with a DC motor's torque-speed curve limiting the torque."""

    class_type: type = DCMotor
    saturation_effort: float = MISSING
    """Peak torque at zero speed [N m]."""
