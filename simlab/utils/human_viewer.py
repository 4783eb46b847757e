"""How ``render_mode="human"`` shows an env: an opener the live viewer registers.

The envs call :func:`open_human_viewer`; the viewer (``simlab.viewer``, a layer above them) fills
the registry when it is imported (``AppLauncher`` and the ``simlab`` command import it).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from simlab.utils.errors import ConfigError

__all__ = ["open_human_viewer", "set_human_viewer_opener"]

_opener: Callable[[Any], Any] | None = None


def set_human_viewer_opener(opener: Callable[[Any], Any]) -> None:
    """``opener(env)`` returns a viewer showing ``env`` (with ``after_step()``), or None if it could not open."""
    global _opener
    _opener = opener


def open_human_viewer(env: Any) -> Any:
    if _opener is None:
        raise ConfigError(
            "render_mode='human' shows the env in simlab's live viewer: import simlab.viewer first "
            "(AppLauncher and the simlab command do), or use render_mode='rgb_array'."
        )
    return _opener(env)
