"""Which live viewer to open: the ``--viewer`` flag, the display, and the app's choice (no heavy imports)."""

from __future__ import annotations

import os

__all__ = ["DEFAULT_PORT", "VIEWER_KINDS", "app_viewer", "display_available", "resolve_viewer_kind", "set_app_viewer"]

VIEWER_KINDS = ("auto", "native", "web", "none")
DEFAULT_PORT = 8080

_app_choice: dict[str, object] = {"kind": "auto", "port": DEFAULT_PORT}


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


def set_app_viewer(kind: str, port: int = DEFAULT_PORT) -> None:
    """Record the viewer the app asked for (``AppLauncher``); ``render_mode="human"`` uses it."""
    _app_choice.update(kind=kind, port=port)


def app_viewer() -> tuple[str, int]:
    """The resolved kind and port the app asked for (``auto`` until an ``AppLauncher`` says)."""
    return resolve_viewer_kind(str(_app_choice["kind"])), int(_app_choice["port"])  # type: ignore[call-overload]
