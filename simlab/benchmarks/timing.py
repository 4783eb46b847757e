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


_memory_baseline: dict[str, int] = {}  # bytes torch still held when a measurement began, per device


def reset_gpu_memory_peak(device: str) -> None:
    """Start a new peak for ``gpu_memory_mb`` (call before building what is measured).

    What an earlier configuration of the same run still holds (objects not yet collected, cached
    kernels' workspaces) is recorded as a baseline and left out of the next figure."""
    if str(device).startswith("cuda"):
        gc.collect()
        torch.cuda.empty_cache()
        torch.cuda.reset_peak_memory_stats(device)
        _memory_baseline[str(device)] = torch.cuda.memory_allocated(device)


def gpu_memory_mb(device: str, physics=None) -> float | None:
    """GPU memory of one benchmark configuration: torch's peak since ``reset_gpu_memory_peak``
    (env buffers, policy, learner) plus the physics' own arrays, which MuJoCo Warp allocates
    outside torch."""
    if not str(device).startswith("cuda"):
        return None
    physics_bytes = physics.device_memory_bytes() if physics is not None else 0
    torch_bytes = torch.cuda.max_memory_allocated(device) - _memory_baseline.get(str(device), 0)
    return (torch_bytes + physics_bytes) / 2**20
