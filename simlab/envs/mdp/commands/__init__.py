"""Command terms and their configs."""

from .commands_cfg import NullCommandCfg, UniformPoseCommandCfg, UniformVelocityCommandCfg
from .null_command import NullCommand
from .pose_command import UniformPoseCommand
from .velocity_command import UniformVelocityCommand

__all__ = [
    "NullCommand",
    "NullCommandCfg",
    "UniformPoseCommand",
    "UniformPoseCommandCfg",
    "UniformVelocityCommand",
    "UniformVelocityCommandCfg",
]
