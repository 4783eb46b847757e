"""The app layer: command-line flags and the app loop object (no Omniverse, launching is instant)."""

from simlab.app.app_launcher import AppLauncher, SimulationApp, resolve_device
from simlab.app.isaaclab3 import add_launcher_args, launch_simulation
from simlab.app.run_tests import run_tests

__all__ = ["AppLauncher", "SimulationApp", "add_launcher_args", "launch_simulation", "resolve_device", "run_tests"]
