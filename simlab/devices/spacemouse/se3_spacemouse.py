"""A 3Dconnexion SpaceMouse as an SE(3) teleoperation device, read over HID (the ``hidapi`` package).

As Isaac Lab's ``Se3SpaceMouse``: the first supported 3Dconnexion device found is opened, a thread
reads its reports (translation, rotation, buttons), ``advance()`` returns the latest command.
``pip install "simlab[teleop]"`` installs hidapi; on Linux the user needs read access to the
device's ``/dev/hidraw*`` node (a udev rule).
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import torch

from ..device_base import DeviceBase, DeviceCfg
from ..se3_command import se3_command

__all__ = ["Se3SpaceMouse", "Se3SpaceMouseCfg", "axis_value"]

SUPPORTED_DEVICES = (
    "SpaceMouse Compact",
    "SpaceMouse Wireless",
    "SpaceNavigator",
    "SpaceNavigator for Notebooks",
    "3Dconnexion Universal Receiver",
)
_VENDOR_IDS = (0x256F, 0x046D)  # 3Dconnexion; Logitech made the older models
_FULL_SCALE = 350.0  # the sensor's report at full deflection


def axis_value(low: int, high: int) -> float:
    """One axis of a SpaceMouse report: a signed 16-bit little-endian number, scaled to about [-1, 1]."""
    value = low | (high << 8)
    if value >= 1 << 15:
        value -= 1 << 16
    return value / _FULL_SCALE


def _load_hid():
    try:
        import hid
    except ImportError as err:
        raise ImportError(f'Se3SpaceMouse reads the device over HID: pip install "simlab[teleop]" ({err})') from err
    return hid


class Se3SpaceMouse(DeviceBase):
    """Delta pose and gripper commands from a SpaceMouse (Isaac Lab's behaviour).

    Push / lift the cap: move the arm; twist / tilt it: rotate the arm. Left button: toggle the
    gripper (and the callback of key ``"L"``); right button: reset the command (and the callback of
    ``"R"``). ``advance()`` returns ``[dx, dy, dz, rx, ry, rz, gripper]`` as :class:`Se3Keyboard` does.
    """

    def __init__(self, cfg: Se3SpaceMouseCfg):
        super().__init__(cfg.retargeters)
        self.cfg = cfg
        self.pos_sensitivity = cfg.pos_sensitivity
        self.rot_sensitivity = cfg.rot_sensitivity
        self.gripper_term = cfg.gripper_term
        self._sim_device = cfg.sim_device
        self._lock = threading.Lock()
        self._close_gripper = False
        self._read_rotation = True
        self._delta_pos = np.zeros(3)
        self._delta_rot = np.zeros(3)
        self._additional_callbacks: dict[str, Callable[[], None]] = {}
        self._device, self._device_name = self._open_device()
        self._running = True
        self._thread = threading.Thread(target=self._read_loop, name="simlab-spacemouse", daemon=True)
        self._thread.start()

    def _open_device(self) -> tuple[Any, str]:
        hid = _load_hid()
        seen, failures = [], []
        for info in hid.enumerate():
            name = info.get("product_string") or ""
            seen.append(f"{name or '?'} ({info['vendor_id']:04x}:{info['product_id']:04x})")
            if info["vendor_id"] not in _VENDOR_IDS or not any(s in name for s in SUPPORTED_DEVICES):
                continue
            device = hid.device()
            try:
                device.open(info["vendor_id"], info["product_id"])
            except OSError as err:
                failures.append(f"{name}: {err} (on Linux, give your user read access to its /dev/hidraw node)")
                continue
            return device, name
        raise OSError(
            f"No SpaceMouse found (supported: {', '.join(SUPPORTED_DEVICES)}). HID devices seen: "
            f"{', '.join(seen) or 'none'}." + (f" Could not open: {'; '.join(failures)}." if failures else "")
        )

    def __str__(self) -> str:
        msg = f"Spacemouse Controller for SE(3): {self.__class__.__name__}\n"
        msg += f"\tProduct: {self._device_name}\n"
        msg += "\t----------------------------------------------\n"
        msg += "\tRight button: reset command\n"
        msg += "\tLeft button: toggle gripper command (open/close)\n"
        msg += "\tMove mouse laterally: move arm horizontally in x-y plane\n"
        msg += "\tMove mouse vertically: move arm vertically\n"
        msg += "\tTwist mouse about an axis: rotate arm about a corresponding axis"
        return msg

    def close(self) -> None:
        """Stop reading and release the device."""
        self._running = False
        self._thread.join(timeout=1.0)

    def reset(self) -> None:
        with self._lock:
            self._close_gripper = False
            self._delta_pos = np.zeros(3)
            self._delta_rot = np.zeros(3)

    def add_callback(self, key: str, func: Callable[[], None]) -> None:
        """``"L"``: called on the left button, ``"R"``: on the right button (other keys never fire)."""
        if not callable(func):
            raise TypeError(f"The callback for '{key}' must be callable, got {type(func).__name__}")
        self._additional_callbacks[str(key)] = func

    def advance(self) -> torch.Tensor:
        with self._lock:
            delta_pos, delta_rot, close = self._delta_pos.copy(), self._delta_rot.copy(), self._close_gripper
        return se3_command(delta_pos, delta_rot, close, self.gripper_term, self._sim_device)

    def _read_loop(self) -> None:
        receiver = self._device_name == "3Dconnexion Universal Receiver"
        while self._running:
            report = self._device.read(13 if receiver else 7, 100)  # 100 ms timeout: notice close()
            if report:
                self.handle_report(list(report), receiver)
        self._device.close()

    def handle_report(self, data: list[int], receiver: bool = False) -> None:
        """Apply one HID report: id 1 translation (and rotation on the receiver), 2 rotation, 3 buttons."""
        callbacks = []
        with self._lock:
            if data[0] == 1:
                self._delta_pos = self.pos_sensitivity * self._xyz(data[1:7])
                if receiver and len(data) >= 13:
                    self._delta_rot = self.rot_sensitivity * self._xyz(data[7:13])
            elif data[0] == 2 and not receiver and self._read_rotation:
                self._delta_rot = self.rot_sensitivity * self._xyz(data[1:7])
            elif data[0] == 3:
                if data[1] == 1:  # left button
                    self._close_gripper = not self._close_gripper
                    callbacks.append("L")
                elif data[1] == 2:  # right button
                    self._close_gripper = False
                    self._delta_pos = np.zeros(3)
                    self._delta_rot = np.zeros(3)
                    callbacks.append("R")
                elif data[1] == 3:  # both: rotation on / off
                    self._read_rotation = not self._read_rotation
        for key in callbacks:
            if key in self._additional_callbacks:
                self._additional_callbacks[key]()

    @staticmethod
    def _xyz(payload: list[int]) -> np.ndarray:
        """The device reports (y, x, -z) in its frame; the arm's (x, y, z)."""
        y, x, z = (axis_value(payload[i], payload[i + 1]) for i in (0, 2, 4))
        return np.array([x, y, -z])


@dataclass
class Se3SpaceMouseCfg(DeviceCfg):
    """Isaac Lab's ``Se3SpaceMouseCfg``."""

    gripper_term: bool = True
    pos_sensitivity: float = 0.4
    rot_sensitivity: float = 0.8
    class_type: type = Se3SpaceMouse
