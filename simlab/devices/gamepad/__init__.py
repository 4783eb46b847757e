"""Gamepad devices (Isaac Lab's ``isaaclab.devices.gamepad``)."""

from .se3_gamepad import Se3Gamepad, Se3GamepadCfg

__all__ = ["Se3Gamepad", "Se3GamepadCfg"]
