"""Actuator configurations: which joints a group drives and with which gains and limits.

Every actuated joint gets one MuJoCo ``general`` actuator with unit gain. For an *implicit*
actuator the model also carries the PD terms as bias, ``force = ctrl - kp * q - kd * qd``, and the
articulation writes ``ctrl = kp * q_target + kd * qd_target + effort_target``: MuJoCo then applies
``kp (q* - q) + kd (qd* - qd) + tau_ff``, clipped to the effort limit, and ``implicitfast``
integrates the damping implicitly, as PhysX drives do. For an *explicit* actuator (ideal PD, DC
motor, delayed and remotized PD, actuator networks) the bias is zero and ``ctrl`` is the torque
computed in torch.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import MISSING
from typing import Literal

from simlab.utils import configclass

from .actuator_net import ActuatorNetLSTM, ActuatorNetMLP
from .actuator_pd import DCMotor, DelayedPDActuator, IdealPDActuator, ImplicitActuator, RemotizedPDActuator


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
    """PD position gain [N/m or N m/rad]. None: the robot file's own, as Isaac Lab takes its USD's drive
    gains; for an implicit drive that is the MJCF joint's ``stiffness`` (moved from the joint's passive
    spring into the drive), for other models 0."""
    damping: dict[str, float] | float | None = MISSING
    """PD velocity gain [N s/m or N m s/rad]. None: the robot file's own, as for ``stiffness`` (the MJCF
    joint's ``damping`` for an implicit drive, else 0)."""
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


@configclass
class DelayedPDActuatorCfg(IdealPDActuatorCfg):
    """Ideal PD on targets that arrive a random number of physics steps late (drawn per env at reset)."""

    class_type: type = DelayedPDActuator
    min_delay: int = 0
    """Smallest delay [physics steps]."""
    max_delay: int = 0
    """Largest delay [physics steps]."""


@configclass
class RemotizedPDActuatorCfg(DelayedPDActuatorCfg):
    """Delayed PD whose torque limit is a function of the joint angle (a linkage-driven joint)."""

    class_type: type = RemotizedPDActuator
    joint_parameter_lookup: list[list[float]] = MISSING
    """Rows of ``(angle [rad], transmission ratio, max torque [N m])``, angles ascending; the limit is
    interpolated linearly in the angle."""


@configclass
class ActuatorNetMLPCfg(DCMotorCfg):
    """An MLP from a history of joint position errors and velocities to torque, clipped as a DC motor.

    ``network_file`` holds the weights only (a state dict read with ``torch.load(weights_only=True)``),
    see :mod:`simlab.actuators.actuator_net`. A TorchScript file is code and is refused unless
    ``trust_network_file`` is True.
    """

    class_type: type = ActuatorNetMLP
    stiffness: dict[str, float] | float | None = None  # the network is the controller
    damping: dict[str, float] | float | None = None

    network_file: str = MISSING
    """Path of the network's weights (Isaac Lab's Nucleus paths of its actuator nets name simlab's own)."""
    trust_network_file: bool = False
    """Load a TorchScript or pickled network as Isaac Lab does (it may run code): only for files you trust."""
    pos_scale: float = MISSING
    """Scale of the joint position errors (target - position) fed to the network."""
    vel_scale: float = MISSING
    """Scale of the joint velocities fed to the network."""
    torque_scale: float = MISSING
    """Scale of the network's output torques."""
    input_order: Literal["pos_vel", "vel_pos"] = MISSING
    """``"pos_vel"``: the position errors first, then the velocities; ``"vel_pos"``: the reverse."""
    input_idx: Iterable[int] = MISSING
    """History steps fed to the network: 0 is the current step, n the n-th step before it."""


@configclass
class ActuatorNetLSTMCfg(DCMotorCfg):
    """An LSTM from the joint position error and velocity of each step to torque, clipped as a DC motor.

    Its hidden state is per env and joint, zeroed at the env's reset. ``network_file`` holds weights
    only, as for :class:`ActuatorNetMLPCfg`.
    """

    class_type: type = ActuatorNetLSTM
    stiffness: dict[str, float] | float | None = None
    damping: dict[str, float] | float | None = None

    network_file: str = MISSING
    """Path of the network's weights (Isaac Lab's Nucleus paths of its actuator nets name simlab's own)."""
    trust_network_file: bool = False
    """Load a TorchScript or pickled network as Isaac Lab does (it may run code): only for files you trust."""
