"""Configuration of the operational-space controller (Isaac Lab's fields and defaults)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import MISSING

from simlab.utils import configclass

from .operational_space import OperationalSpaceController

TARGET_TYPES = ("pose_abs", "pose_rel", "wrench_abs")
IMPEDANCE_MODES = ("fixed", "variable_kp", "variable")
NULLSPACE_CONTROLS = ("none", "position")


@configclass
class OperationalSpaceControllerCfg:
    class_type: type = OperationalSpaceController

    target_types: Sequence[str] = MISSING
    """What the command holds, in order: ``"pose_abs"`` (7: position, quaternion w-first),
    ``"pose_rel"`` (6: translation, rotation vector) and/or ``"wrench_abs"`` (6: force, torque)."""
    motion_control_axes_task: Sequence[int] = (1, 1, 1, 1, 1, 1)
    """Task-frame axes under motion control (x, y, z, rx, ry, rz)."""
    contact_wrench_control_axes_task: Sequence[int] = (0, 0, 0, 0, 0, 0)
    """Task-frame axes under (open-loop) wrench control."""
    inertial_dynamics_decoupling: bool = False
    """Scale the task-space accelerations by the operational-space mass matrix."""
    partial_inertial_dynamics_decoupling: bool = False
    """Decouple translation and rotation separately (ignore their inertial coupling)."""
    gravity_compensation: bool = False
    """Add the joint torques that hold the arm against gravity."""
    impedance_mode: str = "fixed"
    """``"fixed"`` gains; ``"variable_kp"``: the command carries 6 stiffnesses; ``"variable"``: 6
    stiffnesses and 6 damping ratios."""
    motion_stiffness_task: float | Sequence[float] = (100.0, 100.0, 100.0, 100.0, 100.0, 100.0)
    motion_damping_ratio_task: float | Sequence[float] = (1.0, 1.0, 1.0, 1.0, 1.0, 1.0)
    motion_stiffness_limits_task: tuple[float, float] = (0.0, 1000.0)
    motion_damping_ratio_limits_task: tuple[float, float] = (0.0, 100.0)
    contact_wrench_stiffness_task: float | Sequence[float] | None = None
    """Closed-loop force control: the wrench command becomes ``F + Kf (F - f)`` with ``f`` the measured
    contact force (``compute``'s ``current_ee_force_b``); None applies the wrench target open-loop."""
    nullspace_control: str = "none"
    """``"position"`` drives the joints towards a posture inside the task's null space."""
    nullspace_stiffness: float = 10.0
    nullspace_damping_ratio: float = 1.0

    def __post_init__(self):
        if self.target_types is not MISSING:
            bad = [t for t in self.target_types if t not in TARGET_TYPES]
            if bad or not self.target_types:
                raise ValueError(f"target_types {list(self.target_types)!r}: each must be one of {TARGET_TYPES}")
            if "pose_abs" in self.target_types and "pose_rel" in self.target_types:
                raise ValueError("target_types: choose one of 'pose_abs' and 'pose_rel'")
        if self.impedance_mode not in IMPEDANCE_MODES:
            raise ValueError(f"impedance_mode {self.impedance_mode!r}: use one of {IMPEDANCE_MODES}")
        if self.nullspace_control not in NULLSPACE_CONTROLS:
            raise ValueError(f"nullspace_control {self.nullspace_control!r}: use one of {NULLSPACE_CONTROLS}")
