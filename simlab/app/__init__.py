"""The app layer: command-line flags and the app loop object (no Omniverse, launching is instant)."""

from simlab.app.app_launcher import AppLauncher, SimulationApp, resolve_device
from simlab.app.run_tests import run_tests

__all__ = ["AppLauncher", "SimulationApp", "add_launcher_args", "resolve_device", "run_tests"]

add_launcher_args = AppLauncher.add_app_launcher_args
"""Isaac Lab 3.0's name of ``AppLauncher.add_app_launcher_args(parser)``."""
