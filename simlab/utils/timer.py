"""A small wall-clock timer, usable as an object, a context manager or a decorator (Isaac Lab's API)."""

from __future__ import annotations

import time
from contextlib import ContextDecorator
from typing import Any, ClassVar

__all__ = ["Timer", "TimerError"]


class TimerError(RuntimeError):
    """A timer was used out of order (stopped before started, started twice, unknown name)."""


class Timer(ContextDecorator):
    """Measure wall-clock seconds.

    Example::

        with Timer("rollout") as t:       # prints "rollout: 0.123456 seconds" at exit
            run()
        t.total_run_time                   # seconds from start to stop
        with Timer(name="physics"):
            step()
        Timer.get_timer_info("physics")    # the last run of every named timer is kept

    While running, :attr:`time_elapsed` (alias :attr:`elapsed`) reads the time so far.
    """

    timing_info: ClassVar[dict[str, float]] = {}
    """Duration of the last run of each named timer (seconds)."""

    def __init__(self, msg: str | None = None, name: str | None = None):
        self.msg = msg
        self.name = name
        self._start: float | None = None
        self._stop: float | None = None

    def start(self) -> Timer:
        if self.is_running:
            raise TimerError("Timer is running: call stop() before starting it again.")
        self._start, self._stop = time.perf_counter(), None
        return self

    def stop(self) -> float:
        if self._start is None:
            raise TimerError("Timer.stop() called before Timer.start().")
        if self._stop is not None:
            raise TimerError("Timer is not running: it was already stopped.")
        self._stop = time.perf_counter()
        if self.name is not None:
            Timer.timing_info[self.name] = self.total_run_time
        return self.total_run_time

    @property
    def is_running(self) -> bool:
        return self._start is not None and self._stop is None

    @property
    def time_elapsed(self) -> float:
        """Seconds since start (up to stop, once stopped); 0.0 before start."""
        if self._start is None:
            return 0.0
        end = self._stop if self._stop is not None else time.perf_counter()
        return end - self._start

    elapsed = time_elapsed

    @property
    def total_run_time(self) -> float:
        """Seconds from start to stop of the last run; 0.0 if it was never stopped."""
        if self._start is None or self._stop is None:
            return 0.0
        return self._stop - self._start

    @staticmethod
    def get_timer_info(name: str) -> float:
        """Duration of the last run of the timer called ``name``."""
        if name not in Timer.timing_info:
            raise TimerError(f"No timer named '{name}' has run yet; known: {sorted(Timer.timing_info)}.")
        return Timer.timing_info[name]

    def __enter__(self) -> Timer:
        return self.start()

    def __exit__(self, *exc: Any) -> None:
        self.stop()
        if self.msg is not None:
            print(f"{self.msg}: {self.total_run_time:0.6f} seconds")

    def __str__(self) -> str:
        return f"{self.time_elapsed:0.6f}"

    def __repr__(self) -> str:
        return f"Timer(msg={self.msg!r}, name={self.name!r}, elapsed={self.time_elapsed:.6f})"
