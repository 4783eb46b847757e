"""Key events from the live viewers to whoever listens (a teleoperation keyboard, a script's callbacks).

The viewers are where a person types: the native viewer forwards MuJoCo's window key presses, the
web viewer forwards its teleoperation buttons. Neither reports every release: MuJoCo's passive
viewer calls back on presses only, and a web button held down repeats its event while held. Both
therefore send *taps* (a press whose release will not be reported); a listener decides how long a
tap holds its key. A source that does report releases sends ``press`` and ``release``.

Listeners subscribe with the keys they use and a label for each (shown on the web viewer's
buttons); a viewer forwards a key only if someone listens for it, so its own bindings keep working
otherwise.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

__all__ = ["KEY_EVENT_KINDS", "KeyEvent", "KeyListener", "glfw_key_name", "key_hub"]

KEY_EVENT_KINDS = ("press", "release", "tap")


@dataclass(frozen=True)
class KeyEvent:
    """``key``: the key's name as Isaac Lab writes it (``"W"``, ``"K"``); ``kind``: press, release or tap."""

    key: str
    kind: Literal["press", "release", "tap"]

    def __post_init__(self):
        if self.kind not in KEY_EVENT_KINDS:
            raise ValueError(f"Unknown key event kind '{self.kind}'; allowed: {KEY_EVENT_KINDS}")


@dataclass
class KeyListener:
    """A subscriber: the keys it uses (name -> label), which of them act while held (the others act
    once per press), and the function that gets their events."""

    keys: dict[str, str]
    held: frozenset[str]
    on_event: Callable[[KeyEvent], None]


class KeyHub:
    """The subscribers and the viewers that want to know when the subscribed keys change."""

    def __init__(self):
        self._lock = threading.Lock()
        self._listeners: list[KeyListener] = []
        self._watchers: list[Callable[[], None]] = []

    def subscribe(
        self, keys: dict[str, str], on_event: Callable[[KeyEvent], None], held: tuple[str, ...] = ()
    ) -> KeyListener:
        unknown = set(held) - set(keys)
        if unknown:
            raise ValueError(f"Held keys {sorted(unknown)} are not among the subscribed keys {sorted(keys)}")
        listener = KeyListener(dict(keys), frozenset(held), on_event)
        with self._lock:
            self._listeners.append(listener)
            watchers = list(self._watchers)
        for watcher in watchers:
            watcher()
        return listener

    def unsubscribe(self, listener: KeyListener) -> None:
        with self._lock:
            if listener in self._listeners:
                self._listeners.remove(listener)
            watchers = list(self._watchers)
        for watcher in watchers:
            watcher()

    def watch(self, on_change: Callable[[], None]) -> Callable[[], None]:
        """Call ``on_change`` when a listener comes or goes (a viewer rebuilding its buttons)."""
        with self._lock:
            self._watchers.append(on_change)
        return on_change

    def unwatch(self, on_change: Callable[[], None]) -> None:
        with self._lock:
            if on_change in self._watchers:
                self._watchers.remove(on_change)

    def keys(self) -> dict[str, str]:
        """Every key some listener uses, with its label (the first listener's)."""
        with self._lock:
            listeners = list(self._listeners)
        merged: dict[str, str] = {}
        for listener in listeners:
            for key, label in listener.keys.items():
                merged.setdefault(key, label)
        return merged

    def held_keys(self) -> set[str]:
        """The keys some listener acts on while they are held."""
        with self._lock:
            return set().union(*(listener.held for listener in self._listeners))

    def wants(self, key: str) -> bool:
        return key in self.keys()

    def publish(self, event: KeyEvent) -> bool:
        """Hand ``event`` to every listener of its key; True if one listened."""
        with self._lock:
            listeners = [listener for listener in self._listeners if event.key in listener.keys]
        for listener in listeners:
            listener.on_event(event)
        return bool(listeners)


key_hub = KeyHub()
"""The process's hub: the viewers publish to it, the devices subscribe to it."""


def glfw_key_name(keycode: int) -> str | None:
    """The name of a GLFW key code as MuJoCo's viewer reports it: letters and digits, else None."""
    if ord("A") <= keycode <= ord("Z") or ord("0") <= keycode <= ord("9"):
        return chr(keycode)
    return None
