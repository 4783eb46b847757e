"""A scripted SE(3) device: replays keys of Isaac Lab's keyboard map for set numbers of steps.

For tests and demos without a person at the keyboard: ``Se3ScriptedCfg(script=[("W", 20), ("", 5),
("K", 10), ("Q", 20)])`` holds W for 20 ``advance()`` calls, nothing for 5, toggles the gripper and
waits 10, then holds Q for 20. Each segment presses its keys at its first call and releases them
after its last, through the same key handling as :class:`Se3Keyboard`, so the commands are the
keyboard's. After the script: no motion, the gripper as left; ``finished`` is True.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import torch

from simlab.devices.keys import KeyEvent

from .device_base import DeviceBase, DeviceCfg
from .keyboard.se3_keyboard import KEY_MAP_KEYS, Se3Keyboard, Se3KeyboardCfg

__all__ = ["Se3Scripted", "Se3ScriptedCfg"]


class Se3Scripted(DeviceBase):
    """Replays ``cfg.script``: a list of ``(keys held, number of advance() calls)``."""

    def __init__(self, cfg: Se3ScriptedCfg):
        super().__init__(cfg.retargeters)
        for i, segment in enumerate(cfg.script):
            if not (isinstance(segment, (tuple, list)) and len(segment) == 2):
                raise ValueError(f"Script segment {i} must be (keys, steps), got {segment!r}")
            keys, steps = segment
            unknown = [k for k in str(keys).upper() if k not in KEY_MAP_KEYS]
            if unknown:
                raise ValueError(f"Script segment {i} ({keys!r}) has keys {unknown} outside the key map {KEY_MAP_KEYS}")
            if not isinstance(steps, int) or steps < 1:
                raise ValueError(f"Script segment {i} ({keys!r}) must last an int >= 1 steps, got {steps!r}")
        self.cfg = cfg
        self._keyboard = Se3Keyboard(
            Se3KeyboardCfg(
                gripper_term=cfg.gripper_term,
                pos_sensitivity=cfg.pos_sensitivity,
                rot_sensitivity=cfg.rot_sensitivity,
                sim_device=cfg.sim_device,
            ),
            listen_to_viewer=False,
        )
        self._segment = 0
        self._step_in_segment = 0

    def __str__(self) -> str:
        return f"Scripted SE(3) device: {len(self.cfg.script)} segments, {self.num_steps} steps"

    @property
    def num_steps(self) -> int:
        return sum(steps for _, steps in self.cfg.script)

    @property
    def finished(self) -> bool:
        return self._segment >= len(self.cfg.script)

    def reset(self) -> None:
        """Back to the script's start, the gripper open."""
        self._keyboard.reset()
        self._segment = 0
        self._step_in_segment = 0

    def add_callback(self, key: str, func: Callable[[], None]) -> None:
        self._keyboard.add_callback(key, func)

    def advance(self) -> torch.Tensor:
        if self.finished:
            return self._keyboard.advance()
        keys, steps = self.cfg.script[self._segment]
        keys = str(keys).upper()
        if self._step_in_segment == 0:
            for key in keys:
                self._keyboard.on_key_event(KeyEvent(key, "press"))
        command = self._keyboard.advance()
        self._step_in_segment += 1
        if self._step_in_segment == steps:
            for key in keys:
                self._keyboard.on_key_event(KeyEvent(key, "release"))
            self._segment += 1
            self._step_in_segment = 0
        return command


@dataclass
class Se3ScriptedCfg(DeviceCfg):
    script: list[tuple[str, int]] = field(default_factory=list)
    """``(keys, steps)`` segments: the keys (e.g. ``"W"``, ``"WQ"``, ``""`` for none) held for ``steps`` calls."""
    gripper_term: bool = True
    pos_sensitivity: float = 0.4
    rot_sensitivity: float = 0.8
    class_type: type = Se3Scripted
