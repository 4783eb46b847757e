"""Timing helpers shared by the benchmarks: device-synchronised clocks and interleaved rounds."""

from __future__ import annotations

import gc
import statistics
import time
from collections.abc import Callable

import torch


def synchronize(device: str) -> None:
    if str(device).startswith("cuda"):
        torch.cuda.synchronize()


def time_loop(fn: Callable[[], None], steps: int, device: str) -> float:
    """Seconds per call of ``fn`` over ``steps`` calls (device work included)."""
    synchronize(device)
    start = time.perf_counter()
    for _ in range(steps):
        fn()
    synchronize(device)
    return (time.perf_counter() - start) / steps


def interleaved(variants: dict[str, Callable[[], None]], steps: int, device: str, rounds: int = 3) -> dict[str, float]:
    """Median seconds per call of each variant, measured in alternating rounds.

    Alternating the variants spreads the machine's noise (other processes, clocks) over all of
    them, so their ratio is meaningful even when absolute figures drift.
    """
    samples: dict[str, list[float]] = {name: [] for name in variants}
    for _ in range(rounds):
        for name, fn in variants.items():
            samples[name].append(time_loop(fn, steps, device))
    return {name: statistics.median(values) for name, values in samples.items()}


_warp_baseline_bytes = 0
_torch_baseline_bytes = 0  # what torch still held on the current device when a measurement began


def _warp_pool_bytes(device: str) -> int | None:
    """Bytes in Warp's memory pool on ``device`` (every Warp array: the physics, the ray casts' targets,
    graph buffers), or None without a pool."""
    try:
        import warp as wp

        if not wp.is_mempool_enabled(device):
            return None
        return int(wp.get_mempool_used_mem_current(device))
    except Exception:  # noqa: BLE001 - no Warp, or Warp not initialised on this device
        return None


def reset_gpu_memory_peak(device: str) -> None:
    """Start a new peak for ``gpu_memory_mb`` (call before building what is measured).

    What an earlier configuration of the same run still holds (objects not yet collected, cached
    workspaces) is recorded as a baseline and left out of the next figure."""
    global _warp_baseline_bytes, _torch_baseline_bytes
    if str(device).startswith("cuda"):
        gc.collect()  # the previous measurement's env and its Warp arrays
        torch.cuda.empty_cache()
        # the current device's counters (an explicit device is refused before CUDA is initialised)
        torch.cuda.reset_peak_memory_stats()
        _torch_baseline_bytes = torch.cuda.memory_allocated()
        _warp_baseline_bytes = _warp_pool_bytes(device) or 0


def warp_memory_mb(device: str, physics=None) -> float | None:
    """Warp's device memory of one benchmark configuration (call while it is alive): what its memory
    pool gained since ``reset_gpu_memory_peak``, at least the physics' own arrays."""
    if not str(device).startswith("cuda"):
        return None
    physics_bytes = physics.device_memory_bytes() if physics is not None else 0
    pool = _warp_pool_bytes(device)
    pool_bytes = 0 if pool is None else pool - _warp_baseline_bytes
    return max(physics_bytes, pool_bytes) / 2**20


def gpu_memory_mb(device: str, physics=None) -> float | None:
    """GPU memory of one benchmark configuration: torch's peak since ``reset_gpu_memory_peak``
    (env buffers, policy, learner) plus Warp's (``warp_memory_mb``: MuJoCo Warp allocates the
    physics outside torch)."""
    if not str(device).startswith("cuda"):
        return None
    torch_bytes = torch.cuda.max_memory_allocated() - _torch_baseline_bytes
    return torch_bytes / 2**20 + warp_memory_mb(device, physics)
