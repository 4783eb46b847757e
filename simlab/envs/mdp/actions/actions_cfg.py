"""Configurations of the joint action terms (Isaac Lab's names and fields)."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.managers.manager_term_cfg import ActionTermCfg
from simlab.utils import configclass

from . import joint_actions


@configclass
class JointActionCfg(ActionTermCfg):
    joint_names: list[str] = MISSING
    """Joint names or regexes the action drives, one action entry per matched joint."""
    scale: float | dict[str, float] = 1.0
    offset: float | dict[str, float] = 0.0
    preserve_order: bool = False
    """Order the action entries as ``joint_names`` lists them (else the model's joint order)."""


@configclass
class JointPositionActionCfg(JointActionCfg):
    class_type: type = joint_actions.JointPositionAction
    use_default_offset: bool = True
    """Add the default joint positions, so a zero action holds the default pose."""


@configclass
class RelativeJointPositionActionCfg(JointActionCfg):
    class_type: type = joint_actions.RelativeJointPositionAction
    use_zero_offset: bool = True


@configclass
class JointVelocityActionCfg(JointActionCfg):
    class_type: type = joint_actions.JointVelocityAction
    use_default_offset: bool = True


@configclass
class JointEffortActionCfg(JointActionCfg):
    class_type: type = joint_actions.JointEffortAction
