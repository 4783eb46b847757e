"""A gamepad as an SE(3) teleoperation device (Isaac Lab's bindings), read through SDL (pygame-ce).

Isaac Lab reads the gamepad through Omniverse; simlab reads it with SDL's game-controller API
(``pygame._sdl2.controller``), which gives every supported pad the same layout (Xbox names).
``pip install "simlab[teleop]"`` installs pygame-ce. The state is read in ``advance()``.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import torch

from ..device_base import DeviceBase, DeviceCfg
from ..se3_command import se3_command

__all__ = ["Se3Gamepad", "Se3GamepadCfg"]

_AXIS_MAX = 32767.0
_BUTTONS = ("A", "B", "X", "Y", "BACK", "GUIDE", "START", "LEFTSTICK", "RIGHTSTICK", "LEFTSHOULDER",
            "RIGHTSHOULDER", "DPAD_UP", "DPAD_DOWN", "DPAD_LEFT", "DPAD_RIGHT")  # fmt: skip


def _load_sdl_controller():
    """pygame and its SDL game-controller module, started; a clear error without them."""
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    try:
        import pygame
        from pygame._sdl2 import controller
    except ImportError as err:
        raise ImportError(
            f'Se3Gamepad reads the gamepad with pygame-ce (SDL): pip install "simlab[teleop]" ({err})'
        ) from err
    if not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
        os.environ.setdefault("SDL_VIDEODRIVER", "dummy")  # SDL's event pump needs a video driver
    pygame.display.init()
    controller.init()
    return pygame, controller


class Se3Gamepad(DeviceBase):
    """Delta pose and gripper commands from a gamepad (Isaac Lab's bindings).

    ============================ ========================= =========================
    What                         + axis                    - axis
    ============================ ========================= =========================
    Toggle gripper (open/close)  X button
    Move along x                 Left stick up             Left stick down
    Move along y                 Left stick right          Left stick left
    Move along z                 Right stick up            Right stick down
    Rotate about x (roll)        D-pad left                D-pad right
    Rotate about y (pitch)       D-pad down                D-pad up
    Rotate about z (yaw)         Right stick right         Right stick left
    ============================ ========================= =========================

    Sticks scale ``pos_sensitivity`` / ``rot_sensitivity`` by how far they are pushed (values below
    ``dead_zone`` count as 0); the d-pad gives 0.8 ``rot_sensitivity``, as in Isaac Lab.
    ``advance()`` returns ``[dx, dy, dz, rx, ry, rz, gripper]`` as :class:`Se3Keyboard` does.
    """

    def __init__(self, cfg: Se3GamepadCfg):
        super().__init__(cfg.retargeters)
        self.cfg = cfg
        self.pos_sensitivity = cfg.pos_sensitivity
        self.rot_sensitivity = cfg.rot_sensitivity
        self.dead_zone = cfg.dead_zone
        self.gripper_term = cfg.gripper_term
        self._sim_device = cfg.sim_device
        self._pump: Callable[[], None] = lambda: None
        self._controller = self._open_controller(cfg.device_index)
        self._close_gripper = False
        self._buttons_down: set[str] = set()
        self._additional_callbacks: dict[str, Callable[[], None]] = {}

    def _open_controller(self, index: int) -> Any:
        """The SDL game controller ``index``; an error naming what is connected if it is not there."""
        pygame, controller = _load_sdl_controller()
        count = controller.get_count()
        pads = [i for i in range(count) if controller.is_controller(i)]
        if index not in pads:
            raise OSError(
                f"No gamepad at index {index}: SDL sees {len(pads)} gamepad(s) (indices {pads}). Connect one,"
                " or pick another with Se3GamepadCfg(device_index=...)."
            )
        self._pump = pygame.event.pump
        self._pygame = pygame
        return controller.Controller(index)

    def __str__(self) -> str:
        name = getattr(self._controller, "name", "?")
        msg = f"Gamepad Controller for SE(3): {self.__class__.__name__}\n"
        msg += f"\tDevice name: {name}\n"
        msg += "\t----------------------------------------------\n"
        msg += "\tToggle gripper (open/close): X\n"
        msg += "\tMove arm along x-axis: Left Stick Up/Down\n"
        msg += "\tMove arm along y-axis: Left Stick Right/Left\n"
        msg += "\tMove arm along z-axis: Right Stick Up/Down\n"
        msg += "\tRotate arm along x-axis: D-Pad Left/Right\n"
        msg += "\tRotate arm along y-axis: D-Pad Down/Up\n"
        msg += "\tRotate arm along z-axis: Right Stick Right/Left"
        return msg

    def reset(self) -> None:
        self._close_gripper = False

    def add_callback(self, key: str, func: Callable[[], None]) -> None:
        """Call ``func`` when button ``key`` (SDL's names: A, B, X, Y, START, BACK, ...) is pressed.

        Names that are no gamepad button (the teleop script's "R", "STOP") are accepted and never fire.
        """
        if not callable(func):
            raise TypeError(f"The callback for button '{key}' must be callable, got {type(func).__name__}")
        self._additional_callbacks[str(key).upper()] = func

    def advance(self) -> torch.Tensor:
        self._pump()
        axis = self._axes()
        pressed = {name for name in _BUTTONS if self._button(name)}
        new_presses = pressed - self._buttons_down
        self._buttons_down = pressed
        if "X" in new_presses:
            self._close_gripper = not self._close_gripper
        for name in new_presses:
            if name in self._additional_callbacks:
                self._additional_callbacks[name]()
        delta_pos = self.pos_sensitivity * np.array([-axis["LEFTY"], axis["LEFTX"], -axis["RIGHTY"]])
        dpad = 0.8 * self.rot_sensitivity
        roll = dpad * (("DPAD_LEFT" in pressed) - ("DPAD_RIGHT" in pressed))
        pitch = dpad * (("DPAD_DOWN" in pressed) - ("DPAD_UP" in pressed))
        yaw = self.rot_sensitivity * axis["RIGHTX"]
        return se3_command(delta_pos, np.array([roll, pitch, yaw]), self._close_gripper, self.gripper_term,
                           self._sim_device)  # fmt: skip

    def _axes(self) -> dict[str, float]:
        values = {}
        for name in ("LEFTX", "LEFTY", "RIGHTX", "RIGHTY"):
            value = self._controller.get_axis(getattr(self._pygame, f"CONTROLLER_AXIS_{name}")) / _AXIS_MAX
            values[name] = 0.0 if abs(value) < self.dead_zone else float(np.clip(value, -1.0, 1.0))
        return values

    def _button(self, name: str) -> bool:
        return bool(self._controller.get_button(getattr(self._pygame, f"CONTROLLER_BUTTON_{name}")))


@dataclass
class Se3GamepadCfg(DeviceCfg):
    """Isaac Lab's ``Se3GamepadCfg`` and simlab's ``device_index`` (which SDL game controller)."""

    gripper_term: bool = True
    dead_zone: float = 0.01
    pos_sensitivity: float = 1.0
    rot_sensitivity: float = 1.6
    device_index: int = 0
    class_type: type = Se3Gamepad
