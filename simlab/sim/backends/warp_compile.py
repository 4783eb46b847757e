"""Compile the Warp kernels a physics call needs on a thread pool, while start-up goes on.

Warp compiles a kernel module the first time one of its kernels is launched, one module after
another: on a machine whose kernel cache is empty, the first captures of MuJoCo Warp's ``step`` and
``forward`` compile some 30 modules in a row, most of a first run's start-up. Which modules a call
needs is only known by running it, since MuJoCo Warp builds kernels for the model at hand (one per
collision pair type, solver variants, ...).

:func:`compile_ahead` finds them without running anything. It records the call into a capture that
is thrown away, while ``Module.load`` only notes each module it is asked for and answers "not
loaded", which makes ``wp.launch`` return without launching (:func:`_noting_loads`). The noted
modules then compile on a thread pool (Warp's compilers release the GIL; ``wp.force_load`` loads in
parallel the same way) while simlab goes on building the env and the RL library; the first real
capture waits for them (:meth:`Precompile.wait`). A query that needs a loaded module during the dry
pass (``wp.get_suggested_block_size`` of MuJoCo Warp's collision kernels) ends that pass early: its
module compiles with the others and the next pass goes further, a few passes at most.

Nothing here changes what runs: a module the dry pass missed compiles at its first launch, as it
would without it; any error in a dry pass only ends the look-ahead. ``Module.load`` is Warp's
internal API, so this runs only with the Warp release it was checked with (``utils/versions.py``)
and can be turned off with ``SIMLAB_COMPILE_AHEAD=0`` (``simlab bench startup`` compares both).
"""

from __future__ import annotations

import contextlib
import os
import time
from collections.abc import Callable, Iterator
from concurrent.futures import Future, ThreadPoolExecutor
from typing import Any

from simlab.utils.errors import ConfigError
from simlab.utils.versions import release_mismatch, warn_once

MAX_PASSES = 8
"""Dry passes at most: each ends at the first query that needs a loaded module (one per
collision pair type of the model), and the modules found so far compile before the next."""


def compile_ahead_enabled() -> bool:
    """Whether :func:`compile_ahead` may run: not turned off, and the checked Warp release."""
    setting = os.environ.get("SIMLAB_COMPILE_AHEAD", "1")
    if setting not in ("0", "1"):
        raise ConfigError(f"SIMLAB_COMPILE_AHEAD={setting!r}: use 1 (compile Warp's kernels ahead, the default) or 0")
    if setting == "0":
        return False
    mismatch = release_mismatch("warp-lang")
    if mismatch is not None:
        warn_once(f"{mismatch}: Warp kernels compile one by one at their first launch (no compile-ahead)")
        return False
    return True


class Precompile:
    """Modules compiling on a thread pool; :meth:`wait` before the first real capture."""

    def __init__(self, futures: list[Future], pool: ThreadPoolExecutor | None, passes: int, modules: int):
        self._futures = futures
        self._pool = pool
        self.passes = passes
        self.modules = modules
        self.wait_seconds = 0.0  # how long the first capture waited for the pool (diagnostics)

    def wait(self) -> None:
        """Block until every module has compiled; a module that failed compiles (and raises) again
        at its launch, where the error belongs."""
        if self._pool is None:
            return
        start = time.perf_counter()
        _settle(self._futures)
        self._futures = []
        self._pool.shutdown(wait=True)
        self._pool = None
        self.wait_seconds += time.perf_counter() - start


def compile_ahead(wp: Any, device: Any, calls: list[Callable[[], None]], workers: int | None = None) -> Precompile:
    """Start compiling every Warp module ``calls`` launch on ``device``; return at once.

    ``calls`` are run dry (nothing launches, nothing is written) inside throwaway captures; the
    modules they would load compile in the background. Earlier passes' modules must be loaded for
    a later pass to get past a query, so passes after the first wait for the pool first.
    """
    workers = workers or min(os.cpu_count() or 1, 16)
    pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="simlab-warp-compile")
    futures: list[Future] = []
    submitted: set[tuple[int, Any]] = set()
    passes = 0
    for call in calls:
        for _ in range(MAX_PASSES):
            passes += 1
            noted: list[tuple[Any, Any]] = []
            finished = _dry_run(wp, device, call, noted)
            fresh = [(module, block_dim) for module, block_dim in noted if (id(module), block_dim) not in submitted]
            for module, block_dim in fresh:
                submitted.add((id(module), block_dim))
                futures.append(pool.submit(module.load, device, block_dim))
            if finished or not fresh:
                break
            _settle(futures)  # the next pass needs these loaded to get past the query
    return Precompile(futures, pool, passes, len(submitted))


def _settle(futures: list[Future]) -> None:
    """Wait for every compilation; one that failed compiles (and raises) again at its launch."""
    for future in futures:
        with contextlib.suppress(Exception):
            future.result()


def _dry_run(wp: Any, device: Any, call: Callable[[], None], noted: list) -> bool:
    """Run ``call`` in a throwaway capture with loads noted, not made; True when it ran to the end."""
    try:
        with (
            _noting_loads(wp, noted),
            wp.ScopedDevice(device),
            wp.ScopedCapture(device=device, force_module_load=False),
        ):
            call()
        return True
    except Exception:  # a query needed a module not yet loaded (or anything else): stop this pass
        return False


@contextlib.contextmanager
def _noting_loads(wp: Any, noted: list) -> Iterator[None]:
    """Within: ``Module.load`` returns a module already loaded, else notes it and returns None."""
    module_class = wp._src.context.Module
    real_load = module_class.load

    def note(module, device, block_dim=None, *args, **kwargs):
        active = block_dim if block_dim is not None else module.options["block_dim"]
        loaded = module.execs.get((wp.get_device(device).context, active))
        if loaded is not None:
            return real_load(module, device, block_dim, *args, **kwargs)  # checks the hash, cheap
        noted.append((module, block_dim))
        return None

    module_class.load = note
    try:
        yield
    finally:
        module_class.load = real_load
