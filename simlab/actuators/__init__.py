"""Actuator models of articulations: implicit PD in MuJoCo, ideal PD and DC motor in torch."""

from .actuator_cfg import ActuatorBaseCfg, DCMotorCfg, IdealPDActuatorCfg, ImplicitActuatorCfg
from .actuator_pd import ActuatorBase, DCMotor, IdealPDActuator, ImplicitActuator
