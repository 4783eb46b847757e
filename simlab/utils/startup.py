"""Start-up milestones of a command, as seconds since its process started.

``simlab train`` marks when its configs, RL library, env, first env step and first training
iteration are ready; ``--verbose`` prints them, and ``simlab bench startup`` reads
that line to say where start-up goes. Marking is a dict write: it costs nothing measurable.
"""

from __future__ import annotations

import gc
import os
import sys
import time

__all__ = [
    "bytecode_hint",
    "cache_report",
    "clear_milestones",
    "compiled_from_source",
    "format_milestones",
    "mark",
    "milestones",
    "pause_collector_for_start_up",
    "phases",
    "resume_collector_after_start_up",
    "seconds_since_process_start",
]

_MILESTONES: dict[str, float] = {}
_COLLECTOR_PAUSED = False

# the line `simlab train --verbose` prints; simlab bench startup parses it
MILESTONES_PREFIX = "[simlab] Start-up milestones (s since the process started):"


# More than this between the process's start and simlab's first import is not Python starting up:
# the process began as a shell that then exec'd Python (bash runs the last command of
# `bash -c "setup && simlab train"` in its own process), and /proc dates it from the shell's start.
_EXEC_GAP_S = 2.0


def seconds_since_process_start() -> float:
    """Wall time since this process started (Linux's /proc; NaN elsewhere).

    When a shell exec'd Python, the process's start is the shell's: then the time since simlab was
    first imported is returned instead (it leaves out the interpreter's own start, a few tenths).
    """
    since_import = time.time() - getattr(sys.modules.get("simlab"), "_IMPORTED_AT", float("nan"))
    try:
        with open("/proc/self/stat") as f:
            start_ticks = int(f.read().rsplit(")", 1)[1].split()[19])  # field 22: starttime
        with open("/proc/uptime") as f:
            uptime = float(f.read().split()[0])
        since_start = uptime - start_ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        return float("nan")
    return since_import if since_start - since_import > _EXEC_GAP_S else since_start


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


def phases(reached: dict[str, float]) -> dict[str, float]:
    """Seconds spent reaching each milestone from the one before (the first from the process start)."""
    spent, before = {}, 0.0
    for name, seconds in reached.items():
        spent[name] = seconds - before
        before = seconds
    return spent


def pause_collector_for_start_up() -> None:
    """Turn Python's cyclic garbage collector off until :func:`resume_collector_after_start_up`.

    Importing torch, torch._dynamo, sympy and MuJoCo Warp creates millions of objects that live as
    long as the process; the collector walks them again and again while they are created (its full
    collections grow with the heap), which took 30-45 % of those imports on 2 CPU cores. Start-up
    makes little garbage, so nothing is lost by collecting none of it. Only a process's own entry
    point (the ``simlab`` command) calls this; a caller of simlab's functions keeps its collector.
    """
    global _COLLECTOR_PAUSED
    if gc.isenabled():
        gc.disable()
        _COLLECTOR_PAUSED = True


def resume_collector_after_start_up() -> None:
    """Undo :func:`pause_collector_for_start_up` (nothing when it did not pause the collector).

    The objects that exist now (modules, the env, the models) are frozen out of later collections
    first, so the collections during training walk only what training creates.
    """
    global _COLLECTOR_PAUSED
    if _COLLECTOR_PAUSED:
        _COLLECTOR_PAUSED = False
        gc.freeze()
        gc.enable()


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


def cache_report() -> dict[str, object]:
    """What this process compiled because no cache had it, so far: Python modules (bytecode) and
    Warp kernel modules.

    A module counts as compiled from source when its cached bytecode is missing (Python may not
    write it) or was written since this process started (it just did). Warp's kernel modules
    compiled here are the kernel cache's entries written since the process started; a run that
    found every kernel cached writes none. Warp's entries are only counted where Warp is imported.
    """
    started = time.time() - seconds_since_process_start()
    modules = [m for m in list(sys.modules.values()) if str(getattr(m, "__file__", None) or "").endswith(".py")]
    compiled = 0
    for module in modules:
        cached = getattr(module, "__cached__", None)
        if isinstance(cached, str):
            try:
                compiled += os.path.getmtime(cached) >= started
            except OSError:
                compiled += 1
    report: dict[str, object] = {
        "python_modules": len(modules),
        "python_modules_compiled": compiled,
        "pycache_prefix": sys.pycache_prefix,
        "dont_write_bytecode": sys.dont_write_bytecode,
    }
    wp = sys.modules.get("warp")
    folder = getattr(getattr(wp, "config", None), "kernel_cache_dir", None)
    if folder and os.path.isdir(folder):
        entries = [os.path.join(folder, entry) for entry in os.listdir(folder)]
        report["warp_kernel_cache_dir"] = folder
        report["warp_kernel_modules_cached"] = len(entries)
        report["warp_kernel_modules_compiled"] = sum(os.path.getmtime(e) >= started for e in entries)
    return report
