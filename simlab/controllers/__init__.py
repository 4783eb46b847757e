"""Task-space controllers (Isaac Lab's ``isaaclab.controllers``): differential inverse kinematics and
operational-space control, batched over envs in torch."""

from .differential_ik import DifferentialIKController
from .differential_ik_cfg import DifferentialIKControllerCfg
from .operational_space import OperationalSpaceController
from .operational_space_cfg import OperationalSpaceControllerCfg

__all__ = [
    "DifferentialIKController",
    "DifferentialIKControllerCfg",
    "OperationalSpaceController",
    "OperationalSpaceControllerCfg",
]
