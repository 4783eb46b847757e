"""A small wall-clock timer, usable as a context manager."""

from __future__ import annotations

import time

__all__ = ["Timer"]


class Timer:
    """Measure wall-clock seconds.

    Example::

        with Timer("rollout") as t:
            run()
        print(t.elapsed)   # seconds; also readable while running
    """

    def __init__(self, msg: str | None = None):
        self.msg = msg
        self._start: float | None = None
        self._stop: float | None = None

    def start(self) -> Timer:
        self._start, self._stop = time.perf_counter(), None
        return self

    def stop(self) -> float:
        if self._start is None:
            raise RuntimeError("Timer.stop() called before Timer.start().")
        self._stop = time.perf_counter()
        return self.elapsed

    @property
    def elapsed(self) -> float:
        """Seconds since start (up to stop, once stopped); 0.0 before start."""
        if self._start is None:
            return 0.0
        end = self._stop if self._stop is not None else time.perf_counter()
        return end - self._start

    def __enter__(self) -> Timer:
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()
        if self.msg is not None:
            print(f"[Timer] {self.msg}: {self.elapsed:.6f} s")

    def __repr__(self) -> str:
        return f"Timer(msg={self.msg!r}, elapsed={self.elapsed:.6f})"
