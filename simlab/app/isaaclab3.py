"""Isaac Lab 3.0's app functions: ``add_launcher_args(parser)`` and ``with launch_simulation(cfg, args):``."""

from __future__ import annotations

import argparse
import contextlib
from collections.abc import Iterator
from typing import Any

from simlab.app.app_launcher import AppLauncher, SimulationApp

__all__ = ["add_launcher_args", "launch_simulation"]


def add_launcher_args(parser: argparse.ArgumentParser) -> None:
    """The app flags (:meth:`AppLauncher.add_app_launcher_args`) and 3.0's ``--viz`` / ``--visualizer``."""
    AppLauncher.add_app_launcher_args(parser)
    if "--viz" not in parser._option_string_actions:  # argparse has no public API for this
        parser.add_argument(
            "--viz",
            "--visualizer",
            dest="visualizer",
            default=None,
            help="Viewer: native, web, none, or Isaac Lab 3.0's newton_gl / kit (native), viser (web).",
        )


@contextlib.contextmanager
def launch_simulation(cfg: Any, args: argparse.Namespace) -> Iterator[SimulationApp]:
    """Within the block, the app of ``args`` runs (a viewer if one is asked for; ``--max_app_steps``) and
    ``env.sim.is_running()`` asks it; the app closes at the end. ``--viz`` picks the viewer as
    ``simlab train --viz`` does. ``cfg`` is an env config or, as 3.0's tutorials pass, a ``SimulationCfg``:
    its device follows ``--device`` when given."""
    from simlab.sim import SimulationCfg, SimulationContext
    from simlab.viewer.choice import viewer_for_visualizer

    visualizer = getattr(args, "visualizer", None)
    if visualizer and getattr(args, "viewer", None) in (None, "auto"):
        args.viewer = viewer_for_visualizer(visualizer)
    launcher = AppLauncher(args)
    if getattr(args, "device", None):
        sim_cfg = cfg if isinstance(cfg, SimulationCfg) else cfg.sim
        sim_cfg.device = launcher.device
    app = launcher.app
    SimulationContext.running_check = app.is_running
    try:
        yield app
    finally:
        SimulationContext.running_check = None
        app.close()
