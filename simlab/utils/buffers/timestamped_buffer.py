"""A cached value and the simulation time it was computed for."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any


@dataclass
class TimestampedBuffer:
    """Cached data and the timestamp of its last update (``-1`` marks it stale).

    The owner allocates ``data`` and sets ``timestamp`` after recomputing it, so a reader can skip
    the work when ``timestamp`` already equals the current simulation time.
    """

    data: Any = None
    timestamp: float = -1.0


def reset_timestamps(buffers: Iterable[TimestampedBuffer | None]) -> None:
    """Mark every buffer stale; ``None`` entries (not allocated yet) are skipped."""
    for buffer in buffers:
        if buffer is not None:
            buffer.timestamp = -1.0
