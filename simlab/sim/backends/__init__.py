"""Physics backends: ``cpu`` (MuJoCo C through mjbatch) and ``cuda`` (MuJoCo Warp).

``CudaBackend`` is imported lazily (module ``__getattr__``) so that importing simlab never needs
warp or mujoco_warp; ``make_backend`` checks for them only when ``cuda`` is asked for.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any

import mujoco

from .base import EnvIds, PhysicsBackend
from .cpu import CpuBackend

if TYPE_CHECKING:
    from .cuda import CudaBackend

__all__ = ["CpuBackend", "CudaBackend", "EnvIds", "PhysicsBackend", "make_backend"]

_CUDA_DEVICE = re.compile(r"cuda(:\d+)?")


def make_backend(model: mujoco.MjModel, num_envs: int, device: str, **options: Any) -> PhysicsBackend:
    """The backend for ``device``: ``"cpu"`` (mjbatch), ``"cuda"`` or ``"cuda:N"`` (MuJoCo Warp).

    ``options`` go to the backend's constructor (``num_threads`` for cpu; ``nconmax``, ``njmax``,
    ``overflow_check_interval`` for cuda).
    """
    if device == "cpu":
        return CpuBackend(model, num_envs, device="cpu", **options)
    if _CUDA_DEVICE.fullmatch(device):
        from .cuda import CudaBackend, require_cuda_backend

        require_cuda_backend(device)  # clear RuntimeError with the install hint
        return CudaBackend(model, num_envs, device=device, **options)
    raise ValueError(f"unknown physics device '{device}': expected 'cpu', 'cuda' or 'cuda:N'")


def __getattr__(name: str) -> Any:
    if name == "CudaBackend":
        from .cuda import CudaBackend

        return CudaBackend
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
