"""Create a teleoperation device from a named config (Isaac Lab's ``create_teleop_device``)."""

from __future__ import annotations

from collections.abc import Callable

from .device_base import DeviceBase, DeviceCfg

__all__ = ["create_teleop_device"]


def create_teleop_device(
    device_name: str, devices_cfg: dict[str, DeviceCfg], callbacks: dict[str, Callable[[], None]] | None = None
) -> DeviceBase:
    """The device ``devices_cfg[device_name]`` with ``callbacks`` (key -> function) bound."""
    if device_name not in devices_cfg:
        raise ValueError(f"No teleop device '{device_name}' configured; configured: {sorted(devices_cfg)}")
    cfg = devices_cfg[device_name]
    device_class = getattr(cfg, "class_type", None)
    if device_class is None:
        raise ValueError(f"The config of teleop device '{device_name}' ({type(cfg).__name__}) has no class_type")
    device = device_class(cfg)
    for key, func in (callbacks or {}).items():
        device.add_callback(key, func)
    return device
