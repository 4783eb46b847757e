"""Start-up milestones of a command, as seconds since its process started.

``simlab train`` marks when its configs, RL library, env, first env step and first training
iteration are ready; ``--verbose`` prints them, and ``scripts/benchmarks/startup_cost.py`` reads
that line to say where start-up goes. Marking is a dict write: it costs nothing measurable.
"""

from __future__ import annotations

import os
import sys

__all__ = [
    "bytecode_hint",
    "clear_milestones",
    "compiled_from_source",
    "format_milestones",
    "mark",
    "milestones",
    "seconds_since_process_start",
]

_MILESTONES: dict[str, float] = {}

# the line `simlab train --verbose` prints; startup_cost.py parses it
MILESTONES_PREFIX = "[simlab] Start-up milestones (s since the process started):"


def seconds_since_process_start() -> float:
    """Wall time since this process started (Linux's /proc; NaN elsewhere)."""
    try:
        with open("/proc/self/stat") as f:
            start_ticks = int(f.read().rsplit(")", 1)[1].split()[19])  # field 22: starttime
        with open("/proc/uptime") as f:
            uptime = float(f.read().split()[0])
        return uptime - start_ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        return float("nan")


def mark(name: str) -> None:
    """Record that ``name`` is reached now; the first mark of a name counts."""
    _MILESTONES.setdefault(name, seconds_since_process_start())


def milestones() -> dict[str, float]:
    """The milestones marked so far, in the order they were reached."""
    return dict(_MILESTONES)


def clear_milestones() -> None:
    """Forget the milestones (a second run in the same process marks its own)."""
    _MILESTONES.clear()


def format_milestones() -> str:
    """One line: ``MILESTONES_PREFIX`` and ``name=seconds`` pairs."""
    pairs = ", ".join(f"{name}={seconds:.2f}" for name, seconds in _MILESTONES.items())
    return f"{MILESTONES_PREFIX} {pairs}"


# large libraries whose import time doubles or worse when Python compiles them from source
_LARGE_LIBRARIES = ("torch", "torch._dynamo", "sympy", "tensordict", "warp", "mujoco_warp")


def compiled_from_source(names: tuple[str, ...] = _LARGE_LIBRARIES) -> list[str]:
    """Of the modules ``names`` imported so far, those that have no cached bytecode: Python compiled
    them from source in this process and will again in the next."""
    found = []
    for name in names:
        cached = getattr(sys.modules.get(name), "__cached__", None)
        if isinstance(cached, str) and not os.path.exists(cached):
            found.append(name)
    return found


def bytecode_hint(names: tuple[str, ...] = _LARGE_LIBRARIES) -> str | None:
    """A line for the user when large libraries were compiled from source, else None."""
    uncached = compiled_from_source(names)
    if not uncached:
        return None
    why = "PYTHONDONTWRITEBYTECODE is set" if sys.dont_write_bytecode else "their __pycache__ folders are not writable"
    return (
        f"[simlab] Python compiled {', '.join(uncached)} from source in this start-up and will again next time "
        f"({why}), which can double the start-up. Keep a bytecode cache: export PYTHONPYCACHEPREFIX=~/.cache/pycache "
        "(with PYTHONDONTWRITEBYTECODE unset), or run python -m compileall on the install."
    )
