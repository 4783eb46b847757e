"""Teleoperation devices (Isaac Lab's ``isaaclab.devices``).

* :class:`Se3Keyboard`: keys typed in simlab's live viewer (native window or web page), Isaac Lab's map.
* :class:`Se3Gamepad`: a gamepad through SDL (pygame-ce); :class:`Se3SpaceMouse`: a 3Dconnexion
  SpaceMouse over HID (hidapi). Both need ``pip install "simlab[teleop]"`` and the device; without
  either they raise an error that says which is missing.
* :class:`Se3Scripted`: replays keys of the keyboard map, for tests and demos.

Each ``advance()`` returns Isaac Lab's command: ``[dx, dy, dz, rx, ry, rz, gripper]``.
"""

from .device_base import DeviceBase, DeviceCfg, DevicesCfg
from .gamepad import Se3Gamepad, Se3GamepadCfg
from .keyboard import Se3Keyboard, Se3KeyboardCfg
from .scripted import Se3Scripted, Se3ScriptedCfg
from .spacemouse import Se3SpaceMouse, Se3SpaceMouseCfg
from .teleop_device_factory import create_teleop_device

__all__ = [
    "DeviceBase",
    "DeviceCfg",
    "DevicesCfg",
    "Se3Gamepad",
    "Se3GamepadCfg",
    "Se3Keyboard",
    "Se3KeyboardCfg",
    "Se3Scripted",
    "Se3ScriptedCfg",
    "Se3SpaceMouse",
    "Se3SpaceMouseCfg",
    "create_teleop_device",
]
