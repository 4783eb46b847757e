"""The goal-orientation command of the in-hand task."""

from .commands_cfg import InHandReOrientationCommandCfg
from .orientation_command import InHandReOrientationCommand

__all__ = ["InHandReOrientationCommand", "InHandReOrientationCommandCfg"]
