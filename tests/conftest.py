"""Shared test fixtures: the physics devices to run on, and a fresh SimulationContext per test."""

from __future__ import annotations

import importlib.util
import os
import signal
import sys
import time
from collections.abc import Callable
from types import ModuleType
from typing import Any

import pytest


def pytest_configure(config) -> None:
    """A shell starts a background job (``bash .ci/run &``) with SIGINT ignored, and every process it
    starts inherits that: Python then never raises ``KeyboardInterrupt``, and the tests that stop a
    child with Ctrl+C wait for it in vain. With a handler installed here, the children start with
    SIGINT's default handling (exec resets a handled signal, not an ignored one). (A ``preexec_fn``
    per child would do the same but makes subprocess fork this large, multithreaded process.)"""
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)


def load_script(path: str | os.PathLike, name: str | None = None) -> ModuleType:
    """Import a file that is not in a package (a repo script, a ported task file) as module ``name``
    (default: the file's stem), registered in ``sys.modules``: dataclasses, configclass and
    ``torch.jit.script`` look a module up there by name."""
    name = name or os.path.splitext(os.path.basename(path))[0]
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def run_logs(scalars: list[tuple[str, float, int]], prefixes: tuple[str, ...]) -> list[tuple[str, float, int | None]]:
    """The ``(tag, value, step)`` scalars a training logged under ``prefixes``, comparable between two runs:
    rsl_rl's ``.../time`` series are stepped by whole seconds of wall-clock time, so their step is dropped
    (a run that crossed a second under load would differ from an identical one that did not)."""
    return [
        (tag, value, None if tag.endswith("/time") else step)
        for tag, value, step in scalars
        if tag.startswith(prefixes)
    ]


def wait_for(condition: Callable[[], Any], timeout: float, what: str, interval: float = 0.05) -> Any:
    """Poll ``condition()`` until it returns something true, and return that; fail naming ``what``
    after ``timeout`` seconds. Tests wait for the event they need (a file, a line of output) this
    way rather than sleeping a fixed time, which is too short on a loaded machine and wasted on an
    idle one. ``condition`` may itself fail (e.g. assert that a child process still runs)."""
    deadline = time.monotonic() + timeout
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            pytest.fail(f"timed out after {timeout:g} s waiting for {what}")
        time.sleep(interval)


def cuda_available() -> bool:
    try:
        import mujoco_warp  # noqa: F401
        import torch

        return torch.cuda.is_available()
    except ImportError:
        return False


def rendering_available() -> bool:
    """Whether MuJoCo can render offscreen here (simlab tries EGL, then OSMesa: Debian's libosmesa6)."""
    from simlab.utils.gl_backend import GLBackendError, check_gl_backend

    try:
        check_gl_backend()
    except GLBackendError:
        return False
    return True


# Backend-dependent tests take `device`; the cuda case runs on the GPU machine only.
DEVICES = ["cpu", pytest.param("cuda:0", marks=[pytest.mark.gpu])]


def pytest_collection_modifyitems(config, items):
    if cuda_available():
        return
    skip = pytest.mark.skip(reason="needs an NVIDIA GPU and mujoco-warp (pip install 'simlab[gpu]')")
    for item in items:
        if "gpu" in item.keywords:
            item.add_marker(skip)


@pytest.fixture(autouse=True)
def _fresh_simulation():
    """Each test starts without a SimulationContext and leaves none behind."""
    from simlab.sim import SimulationContext

    SimulationContext.clear_instance()
    yield
    SimulationContext.clear_instance()


@pytest.fixture
def one_torch_thread():
    """torch on one thread for the test: two threads on a shared 2-core machine make small PPO
    updates ten times slower (`pytestmark = pytest.mark.usefixtures("one_torch_thread")`)."""
    import torch

    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(threads)
