"""Configurations of the joint action terms (Isaac Lab's names and fields)."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.controllers import DifferentialIKControllerCfg, OperationalSpaceControllerCfg
from simlab.managers.manager_term_cfg import ActionTermCfg
from simlab.utils import configclass

from . import binary_joint_actions, joint_actions, joint_actions_to_limits, task_space_actions


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


@configclass
class JointPositionToLimitsActionCfg(JointActionCfg):
    """``offset`` must stay 0 (Isaac Lab's term has none)."""

    class_type: type = joint_actions_to_limits.JointPositionToLimitsAction
    rescale_to_limits: bool = True
    """Map actions in [-1, 1] onto the joints' soft limits (else the scaled action is the target)."""


@configclass
class EMAJointPositionToLimitsActionCfg(JointPositionToLimitsActionCfg):
    class_type: type = joint_actions_to_limits.EMAJointPositionToLimitsAction
    alpha: float | dict[str, float] = 1.0
    """Weight of the new target in the moving average (1: no smoothing), per joint pattern if a dict."""


@configclass
class BinaryJointActionCfg(ActionTermCfg):
    joint_names: list[str] = MISSING
    """The gripper's finger joints (names or regexes)."""
    open_command_expr: dict[str, float] = MISSING
    """Joint-name patterns to the targets that open the gripper (action >= 0)."""
    close_command_expr: dict[str, float] = MISSING
    """Joint-name patterns to the targets that close it (action < 0)."""


@configclass
class BinaryJointPositionActionCfg(BinaryJointActionCfg):
    class_type: type = binary_joint_actions.BinaryJointPositionAction


@configclass
class BinaryJointVelocityActionCfg(BinaryJointActionCfg):
    class_type: type = binary_joint_actions.BinaryJointVelocityAction


@configclass
class DifferentialInverseKinematicsActionCfg(ActionTermCfg):
    @configclass
    class OffsetCfg:
        """The controlled frame relative to the body: ``pos`` and ``rot`` (w, x, y, z)."""

        pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
        rot: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)

    class_type: type = task_space_actions.DifferentialInverseKinematicsAction
    joint_names: list[str] = MISSING
    body_name: str = MISSING
    """The end-effector body."""
    body_offset: OffsetCfg | None = None
    scale: float | tuple[float, ...] = 1.0
    offset: float | tuple[float, ...] = 0.0
    """Added after scaling: the controller's command is ``action * scale + offset`` (e.g. the centre
    of the workspace, so that actions near zero are reachable targets)."""
    controller: DifferentialIKControllerCfg = MISSING


@configclass
class OperationalSpaceControllerActionCfg(ActionTermCfg):
    @configclass
    class OffsetCfg:
        pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
        rot: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)

    class_type: type = task_space_actions.OperationalSpaceControllerAction
    joint_names: list[str] = MISSING
    body_name: str = MISSING
    body_offset: OffsetCfg | None = None
    task_frame_rel_path: str | None = None
    """Refused unless None: targets are in the robot's root frame."""
    controller_cfg: OperationalSpaceControllerCfg = MISSING
    position_scale: float = 1.0
    orientation_scale: float = 1.0
    wrench_scale: float = 1.0
    stiffness_scale: float = 1.0
    damping_ratio_scale: float = 1.0
    nullspace_joint_pos_target: str = "none"
    """``"none"`` (zeros), ``"center"`` (middle of the joint limits) or ``"default"`` (the default pose)."""

    def __post_init__(self):
        if self.task_frame_rel_path is not None:
            raise ValueError(
                "OperationalSpaceControllerActionCfg.task_frame_rel_path is not supported by simlab; leave it None"
                " (targets are then in the robot's root frame)"
            )
