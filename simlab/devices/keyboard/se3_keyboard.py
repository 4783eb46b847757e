"""A keyboard as an SE(3) teleoperation device, with Isaac Lab's key map, fed by simlab's live viewer.

Isaac Lab reads the keyboard of its Omniverse window; simlab reads the keys typed in its live
viewer (``--viewer native``: MuJoCo's window; ``--viewer web``: the buttons of the page's Teleop
tab) through :data:`simlab.devices.keys.key_hub`. Those viewers report presses only, so a key they
send moves the arm for ``key_hold_time`` seconds of simulated time after its last event (one
``advance()`` per env step; a simulation may run faster than the wall clock, and a tap should move
the arm as far however fast it runs): tap it to nudge, and on the web page hold its button down
(the button repeats while held). Press / release pairs, as a script
or a desktop key source sends them, behave as in Isaac Lab: the key acts until released.
"""

from __future__ import annotations

import threading
import time
import weakref
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import torch

from simlab.devices.keys import KeyEvent, key_hub

from ..device_base import DeviceBase, DeviceCfg
from ..se3_command import se3_command

__all__ = ["KEY_MAP_KEYS", "Se3Keyboard", "Se3KeyboardCfg"]

# Isaac Lab's key map: key -> (position or rotation, axis, sign)
_MOTION_KEYS: dict[str, tuple[str, int, float]] = {
    "W": ("pos", 0, 1.0),
    "S": ("pos", 0, -1.0),
    "A": ("pos", 1, 1.0),
    "D": ("pos", 1, -1.0),
    "Q": ("pos", 2, 1.0),
    "E": ("pos", 2, -1.0),
    "Z": ("rot", 0, 1.0),
    "X": ("rot", 0, -1.0),
    "T": ("rot", 1, 1.0),
    "G": ("rot", 1, -1.0),
    "C": ("rot", 2, 1.0),
    "V": ("rot", 2, -1.0),
}
KEY_MAP_KEYS = (*_MOTION_KEYS, "K", "L")
_KEY_LABELS = {
    "W": "+x", "S": "-x", "A": "+y", "D": "-y", "Q": "+z", "E": "-z",
    "Z": "+roll", "X": "-roll", "T": "+pitch", "G": "-pitch", "C": "+yaw", "V": "-yaw",
    "K": "gripper", "L": "reset",
}  # fmt: skip


class Se3Keyboard(DeviceBase):
    """Delta pose and gripper commands from keys (Isaac Lab's bindings).

    ============================== ========== ==========
    What                           + axis     - axis
    ============================== ========== ==========
    Toggle gripper (open / close)  K
    Reset the command              L
    Move along x                   W          S
    Move along y                   A          D
    Move along z                   Q          E
    Rotate about x (roll)          Z          X
    Rotate about y (pitch)         T          G
    Rotate about z (yaw)           C          V
    ============================== ========== ==========

    ``advance()`` returns ``[dx, dy, dz, rx, ry, rz, gripper]`` (float32 on ``cfg.sim_device``): each
    held key adds ``pos_sensitivity`` (or ``rot_sensitivity``) on its axis, the rotation given as a
    rotation vector, the gripper +1 open and -1 closed (without the gripper if ``gripper_term`` is False).
    """

    def __init__(self, cfg: Se3KeyboardCfg, listen_to_viewer: bool = True):
        """``listen_to_viewer=False``: only events sent to :meth:`on_key_event` count (a scripted device)."""
        super().__init__(cfg.retargeters)
        if cfg.key_hold_time <= 0:
            raise ValueError(f"Se3KeyboardCfg.key_hold_time must be > 0 seconds, got {cfg.key_hold_time}")
        self.cfg = cfg
        self.pos_sensitivity = cfg.pos_sensitivity
        self.rot_sensitivity = cfg.rot_sensitivity
        self.gripper_term = cfg.gripper_term
        self._sim_device = cfg.sim_device
        self._clock: Callable[[], float] = self._simulated_time
        self._advances = 0  # advance() calls: env steps of the loop that drives the device
        self._step_dt: float | None = None  # an env step's simulated seconds, from the simulation
        self._lock = threading.Lock()  # the viewer's thread sends events while the loop advances
        self._pressed: set[str] = set()  # held until released
        self._tapped_until: dict[str, float] = {}  # held until this time
        self._close_gripper = False
        self._additional_callbacks: dict[str, Callable[[], None]] = {}
        self._listener = None
        if listen_to_viewer:
            self._listener = self._subscribe(_KEY_LABELS)

    def _subscribe(self, labels: dict[str, str]):
        """Listen to the hub through a weak reference, so that a dropped keyboard is freed (and unsubscribes)."""
        handler = weakref.WeakMethod(self.on_key_event)

        def forward(event: KeyEvent) -> None:
            method = handler()
            if method is not None:
                method(event)

        return key_hub.subscribe(labels, forward, held=tuple(_MOTION_KEYS))

    def __del__(self):
        listener = getattr(self, "_listener", None)
        if listener is not None:
            key_hub.unsubscribe(listener)

    def close(self) -> None:
        """Stop listening to the viewer's keys."""
        if self._listener is not None:
            key_hub.unsubscribe(self._listener)
            self._listener = None

    def __str__(self) -> str:
        msg = f"Keyboard Controller for SE(3): {self.__class__.__name__}\n"
        msg += "\tKeys come from simlab's live viewer (--viewer native: its window; --viewer web: the Teleop tab)\n"
        msg += "\t----------------------------------------------\n"
        msg += "\tToggle gripper (open/close): K\n"
        msg += "\tMove arm along x-axis: W/S\n"
        msg += "\tMove arm along y-axis: A/D\n"
        msg += "\tMove arm along z-axis: Q/E\n"
        msg += "\tRotate arm along x-axis: Z/X\n"
        msg += "\tRotate arm along y-axis: T/G\n"
        msg += "\tRotate arm along z-axis: C/V"
        return msg

    # -- operations ------------------------------------------------------------------------------

    def reset(self) -> None:
        with self._lock:
            self._close_gripper = False
            self._pressed.clear()
            self._tapped_until.clear()

    def add_callback(self, key: str, func: Callable[[], None]) -> None:
        """Call ``func`` whenever ``key`` is pressed (any key name; keys beyond the map are listened to too)."""
        if not callable(func):
            raise TypeError(f"The callback for key '{key}' must be callable, got {type(func).__name__}")
        self._additional_callbacks[str(key)] = func
        if self._listener is not None:  # listen for the new key as well
            key_hub.unsubscribe(self._listener)
            labels = dict(_KEY_LABELS)
            labels.update({k: labels.get(k, k) for k in self._additional_callbacks})
            self._listener = self._subscribe(labels)

    def _simulated_time(self) -> float:
        """Seconds simulated so far: advance() calls times the env step (Isaac Lab's tasks render once
        per env step, so the simulation's rendering dt is the step); the wall clock without a simulation."""
        if self._step_dt is None:
            from simlab.sim import SimulationContext

            sim = SimulationContext.instance()
            if sim is None:
                return time.monotonic()
            self._step_dt = float(sim.get_rendering_dt())
        return self._advances * self._step_dt

    def advance(self) -> torch.Tensor:
        with self._lock:
            self._advances += 1
            now = self._clock()
            self._tapped_until = {k: t for k, t in self._tapped_until.items() if t > now}
            held = self._pressed | set(self._tapped_until)
            close_gripper = self._close_gripper
        delta = {"pos": np.zeros(3), "rot": np.zeros(3)}
        for key in held:
            kind, axis, sign = _MOTION_KEYS[key]
            delta[kind][axis] += sign * (self.pos_sensitivity if kind == "pos" else self.rot_sensitivity)
        return se3_command(delta["pos"], delta["rot"], close_gripper, self.gripper_term, self._sim_device)

    # -- key events ------------------------------------------------------------------------------

    def on_key_event(self, event: KeyEvent) -> None:
        """Apply a key event (from the viewer's key hub, or sent directly)."""
        key = event.key.upper()
        acts = event.kind in ("press", "tap")
        with self._lock:
            if acts and key == "L":
                self._close_gripper = False
                self._pressed.clear()
                self._tapped_until.clear()
            elif acts and key == "K":
                self._close_gripper = not self._close_gripper
            elif key in _MOTION_KEYS:
                if event.kind == "press":
                    self._pressed.add(key)
                elif event.kind == "release":
                    self._pressed.discard(key)
                    self._tapped_until.pop(key, None)
                else:
                    self._tapped_until[key] = self._clock() + self.cfg.key_hold_time
        callback = self._additional_callbacks.get(key)
        if acts and callback is not None:
            callback()


@dataclass
class Se3KeyboardCfg(DeviceCfg):
    """Isaac Lab's ``Se3KeyboardCfg`` and simlab's ``key_hold_time``."""

    gripper_term: bool = True
    pos_sensitivity: float = 0.4
    rot_sensitivity: float = 0.8
    key_hold_time: float = 0.2
    """Seconds a key sent without a release (a tap from the viewer) keeps acting after its last event."""
    class_type: type = Se3Keyboard
