"""Simulation: configs, the simulation context, spawners and physics backends.

Imported as ``sim_utils`` in Isaac Lab style: ``import simlab.sim as sim_utils``.
"""

from .simulation_cfg import MujocoCfg, SimulationCfg
from .simulation_context import SimulationContext, current_spec, resolve_device
from .spawners import *  # noqa: F403
