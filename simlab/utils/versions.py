"""Code that leans on another library's internals runs only with the release it was checked with.

simlab patches or calls a few things that are not a library's public API: MuJoCo's GL context
choice, ``torch.save`` and ``Normal.sample`` while training or capturing, MuJoCo Warp's private
helpers, Warp's ``Module.load`` (compiling kernels ahead), a copy of rsl_rl's PPO update. Each
site asks :func:`release_mismatch` first; with another release installed it takes the library's
own path and says so in one line (once per process).
The releases are those of ``constraints.txt``, which CI installs.
"""

from __future__ import annotations

import importlib.metadata
import re
import warnings

__all__ = ["CHECKED_RELEASES", "release_mismatch", "warn_once"]

CHECKED_RELEASES = {"torch": "2.13", "mujoco": "3.14", "mujoco-warp": "3.14", "rsl-rl-lib": "5.5", "warp-lang": "1.19"}
"""The releases (leading version parts) whose internals simlab's patches and private calls were checked with."""

_warned: set[str] = set()


def release_mismatch(distribution: str, release: str | None = None) -> str | None:
    """None when the installed ``distribution`` is ``release`` (default: its checked release; "2.13"
    matches 2.13.0+cpu), else one line naming what is installed."""
    release = release or CHECKED_RELEASES[distribution]
    try:
        installed = importlib.metadata.version(distribution)
    except importlib.metadata.PackageNotFoundError:
        return f"{distribution} is not installed"
    wanted = release.split(".")
    if [re.match(r"\d*", part).group() for part in installed.split(".")][: len(wanted)] == wanted:
        return None
    return f"{distribution} {installed} is installed, not {release}"


def warn_once(message: str) -> None:
    """A one-line warning, given once per process."""
    if message not in _warned:
        _warned.add(message)
        warnings.warn(message, stacklevel=3)
