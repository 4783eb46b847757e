"""Batched history buffers (Isaac Lab's ``isaaclab.utils.buffers``)."""

from simlab.utils.buffers.circular_buffer import CircularBuffer
from simlab.utils.buffers.delay_buffer import DelayBuffer
from simlab.utils.buffers.timestamped_buffer import TimestampedBuffer, reset_timestamps

__all__ = ["CircularBuffer", "DelayBuffer", "TimestampedBuffer", "reset_timestamps"]
