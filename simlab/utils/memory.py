"""How much host memory is free, for refusing an allocation that cannot fit before it is tried."""

from __future__ import annotations

import os

from simlab.utils.errors import ConfigError

__all__ = ["available_memory", "check_env_memory", "format_bytes"]


def available_memory() -> int | None:
    """Bytes of host memory this process can still allocate without swapping, or None where unknown.

    The kernel's estimate (``MemAvailable``, or psutil's on other systems), capped by the memory
    limit of the process's cgroup (a container's or a batch job's), which the kernel's figure ignores.
    """
    free = _meminfo_available()
    if free is None:
        try:
            import psutil
        except ImportError:
            return None
        free = int(psutil.virtual_memory().available)
    limit = _cgroup_room()
    return free if limit is None else min(free, limit)


def _meminfo_available() -> int | None:
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


def _cgroup_room() -> int | None:
    """The memory limit of this process's cgroup (v2, or v1's memory controller) minus what the cgroup
    uses, or None without a limit."""
    try:
        with open("/proc/self/cgroup") as f:
            entries = [line.strip().split(":", 2) for line in f]
    except OSError:
        return None
    for controller, root, limit_file, used_file in (
        ("", "/sys/fs/cgroup", "memory.max", "memory.current"),
        ("memory", "/sys/fs/cgroup/memory", "memory.limit_in_bytes", "memory.usage_in_bytes"),
    ):
        path = next((e[2] for e in entries if len(e) == 3 and controller in e[1].split(",")), None)
        if path is None:
            continue
        # the cgroup's own folder; inside a container the namespace's root is mounted in its place
        for folder in (os.path.join(root, path.lstrip("/")), root):
            try:
                with open(os.path.join(folder, limit_file)) as f:
                    limit = f.read().strip()
                with open(os.path.join(folder, used_file)) as f:
                    used = int(f.read().strip())
            except (OSError, ValueError):
                continue
            if limit == "max" or int(limit) >= 2**62:  # no limit (v1 writes a huge number)
                return None
            return max(0, int(limit) - used)
    return None


def format_bytes(count: float) -> str:
    """``1536`` -> ``"1.5 KiB"``: a byte count in binary units."""
    units = ("B", "KiB", "MiB", "GiB", "TiB")
    step = 0
    while abs(count) >= 1024 and step < len(units) - 1:
        count /= 1024
        step += 1
    return f"{count:.0f} B" if step == 0 else f"{count:.1f} {units[step]}"


def check_env_memory(num_envs: int, per_env: int, fixed: int, free: int | None, memory: str = "memory") -> None:
    """Refuse ``num_envs`` envs of ``per_env`` bytes each (plus ``fixed`` bytes) that do not fit in
    ``free`` bytes (None: unknown, nothing is refused), in one line with how many fit."""
    needed = num_envs * per_env + fixed
    if free is None or needed <= free:
        return
    fits = max(0, (free - fixed) // max(per_env, 1))
    raise ConfigError(
        f"{num_envs} envs need about {format_bytes(needed)} of {memory} ({format_bytes(per_env)} per env for "
        f"this model), but {format_bytes(free)} is available: at most about {fits} envs fit "
        "(--num_envs or env.scene.num_envs)."
    )
