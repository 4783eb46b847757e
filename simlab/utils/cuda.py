"""CUDA helpers that are safe to call on CPU-only torch builds."""

from __future__ import annotations

import contextlib
import gc
from collections.abc import Iterator

import torch


def is_capturing() -> bool:
    """Whether the current CUDA stream is recording a graph (False without CUDA)."""
    return torch.cuda.is_available() and torch.cuda.is_current_stream_capturing()


@contextlib.contextmanager
def gc_paused() -> Iterator[None]:
    """Collect garbage now and none during the block (wrap every CUDA-graph capture in it).

    Python's cyclic collector may free an unreachable object that owns a CUDA graph (an env
    nobody closed) at any allocation; destroying a graph while a stream is capturing invalidates
    that capture. torch's ``torch.cuda.graph`` collects on entry for the same reason.
    """
    enabled = gc.isenabled()
    if enabled:  # a paused collector (start-up) collects nothing during the block either
        gc.collect()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()
