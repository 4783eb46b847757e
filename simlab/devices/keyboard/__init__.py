"""Keyboard devices (Isaac Lab's ``isaaclab.devices.keyboard``)."""

from .se3_keyboard import Se3Keyboard, Se3KeyboardCfg

__all__ = ["Se3Keyboard", "Se3KeyboardCfg"]
