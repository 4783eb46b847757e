"""``AppLauncher``: the command-line flags and the app loop object of Isaac Lab, without Omniverse.

There is no simulator application to boot, so launching is instant. The app object keeps Isaac
Lab's script structure working::

    parser = argparse.ArgumentParser()
    AppLauncher.add_app_launcher_args(parser)
    args = parser.parse_args()
    app_launcher = AppLauncher(args)
    simulation_app = app_launcher.app
    ...
    while simulation_app.is_running():
        ...
    simulation_app.close()

Ctrl+C: if the script polls ``is_running()``, the first Ctrl+C makes it return False so the loop
ends cleanly; a second Ctrl+C raises ``KeyboardInterrupt``. Scripts that never poll (e.g. a
training loop) get the ``KeyboardInterrupt`` at once.
"""

from __future__ import annotations

import argparse
import atexit
import difflib
import os
import signal
import sys
import threading
from typing import Any

from simlab.utils.device import resolve_device

__all__ = ["AppLauncher", "SimulationApp", "resolve_device"]


class SimulationApp:
    """The app object scripts loop on: ``is_running()``, ``update()``, ``close()``."""

    def __init__(
        self,
        max_steps: int | None = None,
        install_signal_handler: bool = True,
        viewer: str = "none",
        viewer_port: int = 8080,
        viewer_host: str = "127.0.0.1",
    ):
        self.max_steps = max_steps
        self._viewer_kind = viewer
        self._viewer_port = viewer_port
        self._viewer_host = viewer_host
        self._viewer = None  # opened on the first poll that finds a simulation
        self._viewer_sim = None
        self.num_polls = 0  # calls of is_running()
        self._interrupted = False
        self._closed = False
        self._prev_handler: Any = None
        self._handler_installed = False
        if install_signal_handler and threading.current_thread() is threading.main_thread():
            self._prev_handler = signal.getsignal(signal.SIGINT)
            signal.signal(signal.SIGINT, self._on_sigint)
            self._handler_installed = True
        atexit.register(self.close)

    def _on_sigint(self, signum: int, frame: Any) -> None:
        if self._interrupted or self.num_polls == 0:
            # second Ctrl+C, or a script that never polls is_running(): stop now
            raise KeyboardInterrupt
        self._interrupted = True
        print(
            "\n[simlab] Ctrl+C: stopping at the end of this step (press Ctrl+C again to abort).",
            file=sys.stderr,
        )

    @property
    def viewer(self):
        """The live viewer showing the current simulation, if the app has one open."""
        return self._viewer

    @property
    def interrupted(self) -> bool:
        """True once Ctrl+C was pressed."""
        return self._interrupted

    def is_running(self) -> bool:
        """False once closed, interrupted by Ctrl+C, or polled more than ``max_steps`` times."""
        if self._closed or self._interrupted:
            return False
        self.num_polls += 1
        if self._viewer_kind != "none":
            self._update_viewer()
        return self.max_steps is None or self.num_polls <= self.max_steps

    def _update_viewer(self) -> None:
        """Show the current simulation in the app's viewer: the app loop is where Isaac Sim renders."""
        from simlab.sim import SimulationContext

        sim = SimulationContext.instance()
        if sim is not self._viewer_sim:  # a new simulation (or none): a new viewer
            if self._viewer is not None:
                self._viewer.close()
            self._viewer = self._viewer_sim = None
            if sim is not None and getattr(sim, "physics", None) is not None:  # built (sim.reset() ran)
                from simlab.viewer import open_viewer

                self._viewer_sim = sim
                self._viewer = open_viewer(sim, self._viewer_kind, self._viewer_port, host=self._viewer_host)
        if self._viewer is not None:
            self._viewer.after_step()

    def is_exiting(self) -> bool:
        return not self.is_running()

    def update(self) -> None:
        """Isaac Sim renders a frame here; simlab's viewers are driven by the simulation context."""

    def close(self) -> None:
        """Restore the previous Ctrl+C handler. Safe to call more than once (also runs at exit)."""
        if self._closed:
            return
        self._closed = True
        if self._viewer is not None:
            self._viewer.close()
            self._viewer = None
        if self._handler_installed and threading.current_thread() is threading.main_thread():
            # only restore if nobody replaced our handler in the meantime
            if signal.getsignal(signal.SIGINT) == self._on_sigint:
                signal.signal(signal.SIGINT, self._prev_handler)
            self._handler_installed = False
        atexit.unregister(self.close)

    @property
    def closed(self) -> bool:
        return self._closed


class AppLauncher:
    """Parse the app flags and create the app object.

    Args:
        launcher_args: an ``argparse.Namespace`` (from a parser given to
            :meth:`add_app_launcher_args`) or a dict; keys it does not know are ignored, since
            the script's own flags share the namespace.
        **kwargs: the same settings as keywords; they override ``launcher_args``.
    """

    # flag name -> (default, help)
    _ARGS: dict[str, tuple[Any, str]] = {
        "headless": (False, "Run without a viewer (same as --viewer none)."),
        "viewer": ("auto", "Live viewer: native (MuJoCo's window, needs a display), web (in a browser) or none; "
                   "auto: native with a display, else web."),
        "viewer_port": (8080, "Port of the web viewer."),
        "viewer_host": ("127.0.0.1", "Address the web viewer listens on (0.0.0.0: every network); its printed URL "
                        "carries the token that opens it."),
        "device": (None, "Simulation device: 'cpu', 'cuda' or 'cuda:N'. Default: $SIMLAB_DEVICE, else "
                   "'cuda:0' if a GPU with mujoco_warp is available, else 'cpu'."),
        "enable_cameras": (False, "Enable camera sensors and offscreen rendering."),
        "livestream": (-1, "Accepted for Isaac Lab compatibility and ignored (simlab has no livestreaming)."),
        "experience": ("", "Accepted for Isaac Lab compatibility and ignored (a Kit experience file)."),
        "kit_args": ("", "Accepted for Isaac Lab compatibility and ignored (Kit's command-line settings)."),
        "rendering_mode": (None, "Accepted for Isaac Lab compatibility and ignored (RTX presets; see "
                           "SimulationCfg.render for what MuJoCo's renderer takes)."),
        "max_app_steps": (None, "Stop the app loop (is_running() -> False) after this many iterations. Default: "
                          "$SIMLAB_MAX_APP_STEPS (for scripts that make AppLauncher(headless=...) without the flags)."),
        "verbose": (False, "Print the resolved app settings."),
        # set from the script's own --distributed flag (no app flag, as in Isaac Lab)
        "distributed": (False, "One process per GPU under torchrun: simulate on cuda:<local_rank>."),
    }  # fmt: skip

    def __init__(self, launcher_args: argparse.Namespace | dict | None = None, **kwargs: Any):
        if launcher_args is None:
            settings: dict[str, Any] = {}
        elif isinstance(launcher_args, argparse.Namespace):
            settings = dict(vars(launcher_args))
        elif isinstance(launcher_args, dict):
            settings = dict(launcher_args)
        else:
            raise TypeError(
                f"AppLauncher expects an argparse.Namespace, a dict or None, got {type(launcher_args).__name__}."
            )
        unknown = [k for k in kwargs if k not in self._ARGS]
        if unknown:
            hints = "".join(
                f" ('{k}': did you mean '{c[0]}'?)"
                for k in unknown
                if (c := difflib.get_close_matches(k, self._ARGS, 1))
            )
            raise TypeError(f"AppLauncher got unknown setting(s) {unknown}.{hints} Valid: {list(self._ARGS)}.")
        settings.update(kwargs)
        cfg = {name: settings.get(name, default) for name, (default, _) in self._ARGS.items()}
        for name in ("headless", "enable_cameras", "verbose"):
            if cfg[name] is None:
                cfg[name] = False
            if not isinstance(cfg[name], bool):
                raise TypeError(f"AppLauncher: '{name}' must be a bool, got {cfg[name]!r}.")
        steps = cfg["max_app_steps"]
        if steps is None and os.environ.get("SIMLAB_MAX_APP_STEPS", "").strip():
            text = os.environ["SIMLAB_MAX_APP_STEPS"].strip()
            if not text.isdigit():
                raise ValueError(f"SIMLAB_MAX_APP_STEPS must be an int >= 0, got {text!r}.")
            steps = int(text)
        if steps is not None and (isinstance(steps, bool) or not isinstance(steps, int) or steps < 0):
            raise ValueError(f"AppLauncher: 'max_app_steps' must be None or an int >= 0, got {steps!r}.")
        livestream = cfg["livestream"] if cfg["livestream"] is not None else -1
        if livestream not in (-1, 0, 1, 2):
            raise ValueError(f"AppLauncher: 'livestream' must be one of -1, 0, 1, 2, got {livestream!r}.")
        if livestream > 0:
            print("[simlab] --livestream is ignored: simlab has no livestreaming (use the MuJoCo viewer).")
        kit_only = [f"{name}={cfg[name]!r}" for name in ("experience", "kit_args", "rendering_mode") if cfg[name]]
        if kit_only:
            print(f"[simlab] {', '.join(kit_only)} ignored: they configure Omniverse Kit, which simlab does not run.")

        from simlab.viewer import check_viewer_flags, resolve_viewer_kind, set_app_viewer

        self._headless: bool = cfg["headless"]
        port = cfg["viewer_port"] if cfg["viewer_port"] is not None else 8080
        host = cfg["viewer_host"] if cfg["viewer_host"] is not None else "127.0.0.1"
        check_viewer_flags(cfg["viewer"], port, host, self._headless)
        self._viewer: str = resolve_viewer_kind(cfg["viewer"], self._headless)
        self._viewer_port: int = port
        self._viewer_host: str = host
        set_app_viewer(self._viewer, port, host)
        self._enable_cameras: bool = cfg["enable_cameras"]
        self._verbose: bool = cfg["verbose"]
        self._max_app_steps: int | None = steps
        self._device: str = resolve_device(cfg["device"])
        # ranks of a distributed run (torchrun sets them; JAX_* for skrl's JAX launcher), 0 otherwise
        self.local_rank = 0
        self.global_rank = 0
        if cfg["distributed"]:
            self.local_rank = int(os.environ.get("LOCAL_RANK", "0")) + int(os.environ.get("JAX_LOCAL_RANK", "0"))
            self.global_rank = int(os.environ.get("RANK", "0")) + int(os.environ.get("JAX_RANK", "0"))
            if self._device.startswith("cuda"):
                self._device = resolve_device(f"cuda:{self.local_rank}")
        self._app = SimulationApp(max_steps=steps, viewer=self._viewer, viewer_port=port, viewer_host=host)
        if self._verbose:
            print(
                f"[simlab] AppLauncher: device={self._device} headless={self._headless} viewer={self._viewer} "
                f"enable_cameras={self._enable_cameras} max_app_steps={steps}"
            )

    @staticmethod
    def add_app_launcher_args(parser: argparse.ArgumentParser) -> None:
        """Add the app flags to ``parser``, skipping any flag the script already defined."""
        if not isinstance(parser, argparse.ArgumentParser):
            raise TypeError(f"Expected an argparse.ArgumentParser, got {type(parser).__name__}.")
        existing = parser._option_string_actions  # flag string -> action; argparse has no public API
        group = parser.add_argument_group("app_launcher arguments", "simlab app settings.")
        specs: dict[str, dict[str, Any]] = {
            "headless": {"action": "store_true"},
            "viewer": {"type": str.lower, "choices": ["auto", "native", "web", "none"]},
            "viewer_port": {"type": int},
            "viewer_host": {"type": str},
            "device": {"type": str},
            "enable_cameras": {"action": "store_true"},
            "livestream": {"type": int, "choices": [-1, 0, 1, 2]},
            "experience": {"type": str},
            "kit_args": {"type": str},
            "rendering_mode": {"type": str, "choices": ["performance", "balanced", "quality"]},
            "max_app_steps": {"type": int},
            "verbose": {"action": "store_true"},
        }
        for name, spec in specs.items():
            flag = f"--{name}"
            if flag in existing:
                continue
            default, help_text = AppLauncher._ARGS[name]
            group.add_argument(flag, default=default, help=help_text, **spec)

    @property
    def app(self) -> SimulationApp:
        return self._app

    @property
    def device(self) -> str:
        return self._device

    @property
    def headless(self) -> bool:
        return self._headless

    @property
    def viewer(self) -> str:
        """The live viewer this app shows: ``native``, ``web`` or ``none``."""
        return self._viewer

    @property
    def viewer_port(self) -> int:
        return self._viewer_port

    @property
    def viewer_host(self) -> str:
        return self._viewer_host

    @property
    def enable_cameras(self) -> bool:
        return self._enable_cameras

    @property
    def max_app_steps(self) -> int | None:
        return self._max_app_steps

    @property
    def verbose(self) -> bool:
        return self._verbose
