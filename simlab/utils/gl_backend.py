"""Which OpenGL backend MuJoCo's offscreen renderer uses (``MUJOCO_GL``), chosen by trying them.

A backend is fixed for the life of a process: PyOpenGL binds its platform (``PYOPENGL_PLATFORM``)
at its first import, so a failed try of EGL would leave OSMesa unusable in the same process. The
candidates are therefore tried in short child processes, EGL (GPU drivers) first, then OSMesa
(software), and the first that renders a frame is set in ``os.environ`` for this process and its
children. A ``MUJOCO_GL`` the user set is kept as it is, and checked the same way.
"""

from __future__ import annotations

import ctypes.util
import os
import subprocess
import sys

from simlab.utils.errors import SimlabError

__all__ = [
    "GLBackendError",
    "INSTALL_HINTS",
    "OFFSCREEN_BACKENDS",
    "check_gl_backend",
    "choose_gl_backend",
    "set_aside_missing_backend",
]

OFFSCREEN_BACKENDS = ("egl", "osmesa")
"""Tried in this order when ``MUJOCO_GL`` is unset."""

INSTALL_HINTS = {
    "egl": "EGL needs a GPU driver with EGL (Debian/Ubuntu: apt-get install libegl1, and the GPU's driver)",
    "osmesa": "OSMesa is software rendering (Debian/Ubuntu: apt-get install libosmesa6)",
    "glfw": "GLFW needs a display (set DISPLAY, or run under xvfb-run)",
    "glx": "GLX needs a display (set DISPLAY, or run under xvfb-run)",
}

# Renders one frame of an empty model: what the video recorder will do, in miniature.
_PROBE = (
    "import mujoco\n"
    "m = mujoco.MjModel.from_xml_string('<mujoco/>')\n"
    "r = mujoco.Renderer(m, 8, 8)\n"
    "r.update_scene(mujoco.MjData(m))\n"
    "r.render()\n"
    "r.close()\n"
)

_LIBRARIES = {"osmesa": "OSMesa", "egl": "EGL"}  # the shared library each backend loads at import
_MISSING_VAR = "SIMLAB_MUJOCO_GL_MISSING"  # a MUJOCO_GL set aside because its library is missing

_checked: dict[str, str | None] = {}  # backend -> None if it works, else why it failed


class GLBackendError(SimlabError, RuntimeError):
    """No OpenGL backend can render offscreen here."""


def _try_backend(backend: str, timeout_s: float = 60.0) -> str | None:
    """None if MuJoCo renders a frame with ``MUJOCO_GL=backend`` (in a child process), else why not."""
    if backend in _checked:
        return _checked[backend]
    env = dict(os.environ, MUJOCO_GL=backend)
    env.pop("PYOPENGL_PLATFORM", None)  # MuJoCo's EGL / OSMesa modules set it to match
    try:
        proc = subprocess.run(
            [sys.executable, "-c", _PROBE], env=env, capture_output=True, text=True, timeout=timeout_s
        )
        error = None if proc.returncode == 0 else _last_line(proc.stderr) or f"exit code {proc.returncode}"
    except subprocess.TimeoutExpired:
        error = f"no frame within {timeout_s:.0f} s"
    _checked[backend] = error
    return error


def _last_line(text: str) -> str:
    lines = [line.strip() for line in text.strip().splitlines() if line.strip()]
    return lines[-1] if lines else ""


def set_aside_missing_backend() -> None:
    """Unset a ``MUJOCO_GL`` whose library is not installed, so that ``import mujoco`` works.

    MuJoCo loads the backend's library when it is imported: ``MUJOCO_GL=osmesa`` without
    libOSMesa makes every ``import mujoco`` fail, even where nothing is rendered. simlab calls
    this before it imports mujoco; rendering then reports the missing library.
    """
    requested = os.environ.get("MUJOCO_GL", "").strip().lower()
    library = _LIBRARIES.get(requested)
    if library is not None and ctypes.util.find_library(library) is None:
        del os.environ["MUJOCO_GL"]
        os.environ[_MISSING_VAR] = requested


def choose_gl_backend() -> str:
    """The ``MUJOCO_GL`` backend for offscreen rendering: the user's, else the first that works.

    Raises:
        GLBackendError: the user's ``MUJOCO_GL`` fails, or (unset) neither EGL nor OSMesa works;
            the message says what to install.
    """
    chosen = os.environ.get("MUJOCO_GL", "").strip().lower()
    if chosen:
        return chosen
    missing = os.environ.get(_MISSING_VAR)
    if missing:
        raise GLBackendError(
            f"MUJOCO_GL={missing} is set, but lib{_LIBRARIES[missing]} is not installed. "
            f"{INSTALL_HINTS[missing]}; or unset MUJOCO_GL to let simlab try {' and '.join(OFFSCREEN_BACKENDS)}."
        )
    failures = {}
    for backend in OFFSCREEN_BACKENDS:
        error = _try_backend(backend)
        if error is None:
            os.environ["MUJOCO_GL"] = backend
            return backend
        failures[backend] = error
    tried = "; ".join(f"{name}: {why}" for name, why in failures.items())
    hints = "; ".join(INSTALL_HINTS.get(name, name) for name in failures)
    raise GLBackendError(
        f"No OpenGL backend renders offscreen here (tried {tried}). Install one: {hints}. "
        "Or set MUJOCO_GL to a backend that works here."
    )


def check_gl_backend() -> str:
    """Choose the backend and make sure it renders (call before a run that records videos).

    Raises:
        GLBackendError: with the backend tried and what to install.
    """
    backend = choose_gl_backend()
    error = _try_backend(backend)
    if error is not None:
        hint = INSTALL_HINTS.get(backend, "MUJOCO_GL must be one of egl, osmesa, glfw")
        raise GLBackendError(
            f"Offscreen rendering with MUJOCO_GL={backend} fails here ({error}). {hint}; "
            f"or unset MUJOCO_GL to let simlab try {' and '.join(OFFSCREEN_BACKENDS)}."
        )
    return backend
