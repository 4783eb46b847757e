"""The device string rules: which device a run simulates on (``"cpu"`` or ``"cuda:N"``).

The lowest layer holds them, so that the simulation, the configs and the command line read one rule.
"""

from __future__ import annotations

import importlib.util
import os
import re

from simlab.utils.errors import ConfigError, DeviceError

__all__ = ["gpu_backend_available", "resolve_device"]

_DEVICE_RE = re.compile(r"^(cpu|cuda(:\d+)?)$")


def gpu_backend_available() -> bool:
    """True if mujoco_warp is installed and torch sees a CUDA device."""
    if importlib.util.find_spec("mujoco_warp") is None:
        return False  # decided without importing torch
    import torch

    return torch.cuda.is_available()


def resolve_device(device: str | None) -> str:
    """The device to simulate on: ``"cpu"`` or ``"cuda:N"``.

    ``None`` (or ``"auto"``) reads the ``SIMLAB_DEVICE`` environment variable, and without it picks
    ``"cuda:0"`` when a GPU and mujoco_warp are available, else ``"cpu"``. ``"cuda"`` means
    ``"cuda:0"``. A CUDA device asked for where there is no GPU or no mujoco-warp is an error that
    says how to install the GPU backend.
    """
    if device is None or device == "auto":
        device = os.environ.get("SIMLAB_DEVICE") or None
        if device is None or device == "auto":
            return "cuda:0" if gpu_backend_available() else "cpu"
    if not isinstance(device, str):
        raise ConfigError(f"device must be a string such as 'cpu' or 'cuda:0', got {type(device).__name__}.")
    device = device.strip().lower()
    if not _DEVICE_RE.match(device):
        raise ConfigError(f"Invalid device '{device}'. Allowed: 'cpu', 'cuda', 'cuda:N' (N = GPU index), 'auto'.")
    if device == "cpu":
        return device
    if device == "cuda":
        device = "cuda:0"
    if importlib.util.find_spec("mujoco_warp") is None:
        raise DeviceError(
            f"Device '{device}' needs MuJoCo Warp, which is not installed: pip install \"simlab[gpu]\" "
            "(or run on the CPU with --device cpu)."
        )
    if not gpu_backend_available():
        raise DeviceError(f"Device '{device}' asked for, but torch sees no CUDA GPU here; use --device cpu.")
    import torch

    index = int(device.split(":")[1])
    if index >= torch.cuda.device_count():
        raise DeviceError(f"Device '{device}' does not exist: {torch.cuda.device_count()} CUDA device(s) visible.")
    return device
