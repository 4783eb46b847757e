"""CUDA helpers that are safe to call on CPU-only torch builds."""

from __future__ import annotations

import torch


def is_capturing() -> bool:
    """Whether the current CUDA stream is recording a graph (False without CUDA)."""
    return torch.cuda.is_available() and torch.cuda.is_current_stream_capturing()
