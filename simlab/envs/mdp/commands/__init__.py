"""Command terms and their configs."""

from .commands_cfg import NullCommandCfg, UniformPose2dCommandCfg, UniformPoseCommandCfg, UniformVelocityCommandCfg
from .null_command import NullCommand
from .pose_2d_command import UniformPose2dCommand
from .pose_command import UniformPoseCommand
from .velocity_command import UniformVelocityCommand

__all__ = [
    "NullCommand",
    "NullCommandCfg",
    "UniformPose2dCommand",
    "UniformPose2dCommandCfg",
    "UniformPoseCommand",
    "UniformPoseCommandCfg",
    "UniformVelocityCommand",
    "UniformVelocityCommandCfg",
]
