"""Command terms and their configs."""

from .commands_cfg import NullCommandCfg, UniformVelocityCommandCfg
from .null_command import NullCommand
from .velocity_command import UniformVelocityCommand

__all__ = ["NullCommand", "NullCommandCfg", "UniformVelocityCommand", "UniformVelocityCommandCfg"]
