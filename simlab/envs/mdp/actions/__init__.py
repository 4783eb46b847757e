"""Action terms and their configs."""

from .actions_cfg import (
    BinaryJointActionCfg,
    BinaryJointPositionActionCfg,
    BinaryJointVelocityActionCfg,
    DifferentialInverseKinematicsActionCfg,
    EMAJointPositionToLimitsActionCfg,
    JointActionCfg,
    JointEffortActionCfg,
    JointPositionActionCfg,
    JointPositionToLimitsActionCfg,
    JointVelocityActionCfg,
    OperationalSpaceControllerActionCfg,
    RelativeJointPositionActionCfg,
)
from .binary_joint_actions import BinaryJointAction, BinaryJointPositionAction, BinaryJointVelocityAction
from .joint_actions import (
    JointAction,
    JointEffortAction,
    JointPositionAction,
    JointVelocityAction,
    RelativeJointPositionAction,
)
from .joint_actions_to_limits import EMAJointPositionToLimitsAction, JointPositionToLimitsAction
from .task_space_actions import DifferentialInverseKinematicsAction, OperationalSpaceControllerAction

__all__ = [
    "BinaryJointAction",
    "BinaryJointActionCfg",
    "BinaryJointPositionAction",
    "BinaryJointPositionActionCfg",
    "BinaryJointVelocityAction",
    "BinaryJointVelocityActionCfg",
    "DifferentialInverseKinematicsAction",
    "DifferentialInverseKinematicsActionCfg",
    "EMAJointPositionToLimitsAction",
    "EMAJointPositionToLimitsActionCfg",
    "JointAction",
    "JointActionCfg",
    "JointEffortAction",
    "JointEffortActionCfg",
    "JointPositionAction",
    "JointPositionActionCfg",
    "JointPositionToLimitsAction",
    "JointPositionToLimitsActionCfg",
    "JointVelocityAction",
    "JointVelocityActionCfg",
    "OperationalSpaceControllerAction",
    "OperationalSpaceControllerActionCfg",
    "RelativeJointPositionAction",
    "RelativeJointPositionActionCfg",
]
