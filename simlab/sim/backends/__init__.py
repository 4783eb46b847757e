"""Physics backends: ``cpu`` (MuJoCo C through mjbatch) and ``cuda`` (MuJoCo Warp).

``CudaBackend`` is imported lazily (module ``__getattr__``) so that importing simlab never needs
warp or mujoco_warp; ``make_backend`` checks for them only when ``cuda`` is asked for.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import mujoco

from .base import EnvIds, PhysicsBackend
from .cpu import CpuBackend

if TYPE_CHECKING:
    from .cuda import CudaBackend

__all__ = ["CpuBackend", "CudaBackend", "EnvIds", "PhysicsBackend", "make_backend"]

_CUDA_DEVICE = re.compile(r"cuda(:\d+)?")
ENGINES = ("auto", "mujoco", "mujoco_warp")


def make_backend(
    model: mujoco.MjModel,
    num_envs: int,
    device: str,
    engine: str = "auto",
    num_threads: int = 0,
    nconmax: int | None = None,
    njmax: int | None = None,
    post_constraint_model: Callable[[], mujoco.MjModel] | None = None,
    **cuda_options: Any,
) -> PhysicsBackend:
    """The backend for ``device`` and ``engine`` (``SimulationCfg.engine``).

    ``"cpu"`` runs MuJoCo through mjbatch (``num_threads`` workers), ``"cuda"`` / ``"cuda:N"`` runs
    MuJoCo Warp (``nconmax`` / ``njmax`` contact and constraint buffers per world, and any other
    option of :class:`CudaBackend`, e.g. ``overflow_check_interval``); engine
    ``"mujoco_warp"`` with ``"cpu"`` runs MuJoCo Warp on Warp's CPU device. ``post_constraint_model``
    compiles ``model`` with the post-constraint pass on: the cpu backend's way to run that pass on
    demand (``PhysicsBackend.post_constraint``); MuJoCo Warp launches it by itself.
    """
    if engine not in ENGINES:
        raise ValueError(f"unknown physics engine '{engine}': expected one of {ENGINES}")
    cuda = bool(_CUDA_DEVICE.fullmatch(device))
    if device != "cpu" and not cuda:
        raise ValueError(f"unknown physics device '{device}': expected 'cpu', 'cuda' or 'cuda:N'")
    if cuda and engine == "mujoco":
        raise ValueError(
            f"engine 'mujoco' (MuJoCo C through mjbatch) runs on the CPU only, not on '{device}':"
            " use device 'cpu', or engine 'auto' / 'mujoco_warp' on the GPU"
        )
    if device == "cpu" and engine != "mujoco_warp":
        return CpuBackend(
            model, num_envs, device="cpu", num_threads=num_threads, post_constraint_model=post_constraint_model
        )
    from .cuda import CudaBackend, require_cuda_backend

    require_cuda_backend(device)  # clear RuntimeError with the install hint
    return CudaBackend(model, num_envs, device=device, nconmax=nconmax, njmax=njmax, **cuda_options)


def __getattr__(name: str) -> Any:
    if name == "CudaBackend":
        from .cuda import CudaBackend

        return CudaBackend
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
