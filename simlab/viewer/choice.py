"""Which live viewer to open: the ``--viewer`` flag, the display, and the app's choice (no heavy imports)."""

from __future__ import annotations

import os

__all__ = [
    "DEFAULT_HOST",
    "DEFAULT_PORT",
    "VIEWER_KINDS",
    "app_viewer",
    "check_viewer_flags",
    "display_available",
    "resolve_viewer_kind",
    "set_app_viewer",
    "viewer_for_visualizer",
]

VIEWER_KINDS = ("auto", "native", "web", "none")
DEFAULT_PORT = 8080
DEFAULT_HOST = "127.0.0.1"  # this machine only; --viewer_host 0.0.0.0 opens the web viewer to the network

_app_choice: dict[str, object] = {"kind": "auto", "port": DEFAULT_PORT, "host": DEFAULT_HOST}


def display_available() -> bool:
    """Whether a desktop window can open (an X11 or Wayland display)."""
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def resolve_viewer_kind(kind: str | None, headless: bool = False) -> str:
    """``native``, ``web`` or ``none`` for a ``--viewer`` value (``auto``: native with a display)."""
    kind = (kind or "auto").lower()
    if kind not in VIEWER_KINDS:
        raise ValueError(f"Unknown viewer '{kind}'; allowed: {', '.join(VIEWER_KINDS)}")
    if headless:
        return "none"
    if kind == "auto":
        return "native" if display_available() else "web"
    return kind


def check_viewer_flags(viewer: str | None, port: object, host: object, headless: bool) -> None:
    """Refuse viewer settings that cannot work: a port outside 1..65535, an empty host, and a viewer
    asked for together with ``--headless`` (which shows none)."""
    from simlab.utils.errors import ConfigError

    if isinstance(port, bool) or not isinstance(port, int) or not 1 <= port <= 65535:
        raise ConfigError(f"--viewer_port must be a TCP port, 1 to 65535, got {port!r}.")
    if not isinstance(host, str) or not host.strip():
        raise ConfigError(f"--viewer_host must be an address to listen on, e.g. 127.0.0.1 or 0.0.0.0, got {host!r}.")
    if headless and (viewer or "auto").lower() in ("native", "web"):
        raise ConfigError(f"--headless shows no viewer, but --viewer {viewer} asks for one: give one of them.")


def set_app_viewer(kind: str, port: int = DEFAULT_PORT, host: str = DEFAULT_HOST) -> None:
    """Record the viewer the app asked for (``AppLauncher``); ``render_mode="human"`` uses it."""
    _app_choice.update(kind=kind, port=port, host=host)


def app_viewer() -> tuple[str, int, str]:
    """The resolved kind, port and host the app asked for (``auto`` until an ``AppLauncher`` says)."""
    kind = resolve_viewer_kind(str(_app_choice["kind"]))
    return kind, int(_app_choice["port"]), str(_app_choice["host"])  # type: ignore[call-overload]


# Isaac Lab 3.0's visualizer names (--viz / --visualizer) -> simlab's viewer kinds
VISUALIZERS = {
    "native": "native",
    "web": "web",
    "none": "none",
    "newton_gl": "native",  # Newton's OpenGL window -> MuJoCo's window
    "newton": "native",  # 3.0's deprecated alias of newton_gl
    "kit": "native",  # Isaac Sim's desktop viewport -> MuJoCo's window
    "viser": "web",  # a browser viewer (simlab's web viewer is built on viser too)
}
REFUSED_VISUALIZERS = {
    "rerun": "simlab has no Rerun recorder: use --viz web (a live browser viewer) or --video (MP4 clips)",
    "newton_rtx": "simlab has no path-traced viewer: use --viz native (MuJoCo's window) or --viz web",
}


def viewer_for_visualizer(value: str | list[str] | tuple[str, ...]) -> str:
    """simlab's viewer kind (``native``, ``web``, ``none``) for Isaac Lab 3.0's ``--viz`` value: names
    separated by commas (or a list); a name simlab has no counterpart for is a ConfigError saying what
    to use, and so are two names for different viewers (simlab opens one)."""
    from simlab.utils.errors import ConfigError

    text = value if isinstance(value, str) else ",".join(value)
    names = [name.strip().lower() for name in text.split(",")]
    kinds = []
    for name in names:
        if name in REFUSED_VISUALIZERS:
            raise ConfigError(f"--viz {name}: {REFUSED_VISUALIZERS[name]}.")
        if name not in VISUALIZERS:
            allowed = ", ".join([*VISUALIZERS, *REFUSED_VISUALIZERS])
            raise ConfigError(f"--viz {name or text} is not a visualizer simlab knows; allowed: {allowed}.")
        kinds.append(VISUALIZERS[name])
    if len(set(kinds)) > 1:
        raise ConfigError(f"--viz {text}: simlab opens one live viewer; name one of native, web, none.")
    return kinds[0]
