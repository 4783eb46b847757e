"""Action terms and their configs."""

from .actions_cfg import (
    BinaryJointActionCfg,
    BinaryJointPositionActionCfg,
    BinaryJointVelocityActionCfg,
    DifferentialInverseKinematicsActionCfg,
    JointActionCfg,
    JointEffortActionCfg,
    JointPositionActionCfg,
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
    "JointAction",
    "JointActionCfg",
    "JointEffortAction",
    "JointEffortActionCfg",
    "JointPositionAction",
    "JointPositionActionCfg",
    "JointVelocityAction",
    "JointVelocityActionCfg",
    "OperationalSpaceControllerAction",
    "OperationalSpaceControllerActionCfg",
    "RelativeJointPositionAction",
    "RelativeJointPositionActionCfg",
]
