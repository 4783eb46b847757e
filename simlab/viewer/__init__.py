"""Live viewers: watch envs while they train or play.

* ``native``: MuJoCo's own window, where there is a display.
* ``web``: the scene in a browser (viser / mjviser), for remote machines without one; it listens on
  127.0.0.1 unless given another ``host`` (``--viewer_host``) and shows the scene only to whoever
  opens its printed URL, which carries a random token (``simlab.viewer.access``).
* ``auto``: native with a display, else web. ``none``: no viewer.

``open_viewer`` opens one on an env (or a bare simulation); ``ViewerWrapper`` drives it from a
gymnasium env's steps. With ``steer=True`` (``simlab play``), a velocity task's command of the
followed env is steered from the viewer (``simlab.viewer.steering``). A viewer that cannot open
warns and returns None: runs never depend on it.
``AppLauncher`` records the ``--viewer`` / ``--viewer_port`` / ``--viewer_host`` flags here (``set_app_viewer``), so
``render_mode="human"`` and the tutorial scripts' app loop use the same choice.
"""

from __future__ import annotations

import importlib
import sys
from typing import Any

from simlab.utils.human_viewer import set_human_viewer_opener
from simlab.viewer.choice import (
    DEFAULT_HOST,
    DEFAULT_PORT,
    VIEWER_KINDS,
    app_viewer,
    check_viewer_flags,
    display_available,
    resolve_viewer_kind,
    set_app_viewer,
)

__all__ = [
    "DEFAULT_HOST",
    "DEFAULT_PORT",
    "VIEWER_KINDS",
    "LiveViewer",
    "SimSource",
    "ViewerControls",
    "ViewerError",
    "ViewerWrapper",
    "app_viewer",
    "check_viewer_flags",
    "display_available",
    "open_viewer",
    "resolve_viewer_kind",
    "set_app_viewer",
]

# Imported on first use: the flags above are read by every CLI command, the viewers need mujoco and torch.
_LAZY = {
    "LiveViewer": "simlab.viewer.live",
    "ViewerControls": "simlab.viewer.live",
    "ViewerError": "simlab.viewer.live",
    "SimSource": "simlab.viewer.source",
    "ViewerWrapper": "simlab.viewer.wrapper",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'simlab.viewer' has no attribute '{name}'")


def open_viewer(
    source,
    kind: str = "auto",
    port: int = DEFAULT_PORT,
    realtime: bool = False,
    follow: int = 0,
    host: str = DEFAULT_HOST,
    steer: bool = False,
):
    """A live viewer on ``source`` (an env, a ``SimulationContext`` or a ``SimSource``), or None
    (``kind="none"``, or it could not open: a warning says why). The web viewer listens on ``host:port``.
    ``steer``: let the person steer the env's velocity command (an env with one; call before its first step)."""
    from simlab.viewer.live import ViewerError
    from simlab.viewer.source import SimSource
    from simlab.viewer.steering import VelocitySteering

    kind = resolve_viewer_kind(kind)
    if kind == "none":
        return None
    steering = VelocitySteering.of_env(source) if steer else None
    if not isinstance(source, SimSource):
        source = SimSource.of_env(source) if hasattr(source, "scene") else SimSource.of_sim(source)
    try:
        if kind == "native":
            from simlab.viewer.native import NativeViewer

            return NativeViewer(source, realtime=realtime, follow=follow, steering=steering)
        from simlab.viewer.web import WebViewer

        return WebViewer(source, port=port, realtime=realtime, follow=follow, host=host, steering=steering)
    except ViewerError as err:
        print(f"[simlab] WARNING: no {kind} viewer: {err}. Running without a viewer.", file=sys.stderr)
        return None


def _open_for_human_render(env):
    """``render_mode="human"``: the viewer the app asked for (``--viewer``; else native with a display, web without)."""
    kind, port, host = app_viewer()
    return open_viewer(env, kind, port, host=host)


set_human_viewer_opener(_open_for_human_render)  # the envs, a layer below, open viewers through it
