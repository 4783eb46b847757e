"""The interface of teleoperation devices (Isaac Lab's ``isaaclab.devices.device_base``)."""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import torch

__all__ = ["DeviceBase", "DeviceCfg", "DevicesCfg"]


@dataclass
class DeviceCfg:
    """What every device config has: the device its commands are put on, and retargeters (none in simlab)."""

    sim_device: str = "cpu"
    retargeters: list = field(default_factory=list)
    class_type: type | None = None


@dataclass
class DevicesCfg:
    """Named device configs an env config may offer (``env_cfg.teleop_devices``)."""

    devices: dict[str, DeviceCfg] = field(default_factory=dict)


class DeviceBase(ABC):
    """A teleoperation device: ``advance()`` gives the next command, ``reset()`` clears it,
    ``add_callback(key, func)`` runs ``func`` when ``key`` is pressed."""

    def __init__(self, retargeters: list | None = None):
        if retargeters:
            raise NotImplementedError(
                "simlab's devices have no retargeters (Isaac Lab's OpenXR stack): leave cfg.retargeters empty."
            )
        self._retargeters: list = []

    def __str__(self) -> str:
        return f"{self.__class__.__name__}"

    @abstractmethod
    def reset(self) -> None:
        """Clear the command (and any toggled state)."""

    @abstractmethod
    def add_callback(self, key: Any, func: Callable[[], None]) -> None:
        """Call ``func`` (no arguments) whenever ``key`` is pressed."""

    @abstractmethod
    def advance(self) -> torch.Tensor:
        """The command for the next env step."""

    def push_force(self, forces, names=None, frame: str = "world", position=None) -> None:
        """Haptic feedback: devices without it ignore the call (as in Isaac Lab)."""
        return None
