"""Simulation: configs, the simulation context, spawners and physics backends.

Imported as ``sim_utils`` in Isaac Lab style: ``import simlab.sim as sim_utils``.
"""

from . import utils
from .converters import AssetConverterBaseCfg, UrdfConverter, UrdfConverterCfg
from .simulation_cfg import MujocoCfg, PhysxCfg, RenderCfg, SimulationCfg
from .simulation_context import (
    SimulationContext,
    build_simulation_context,
    compute_body_interaction_forces,
    current_spec,
    resolve_device,
)
from .spawners import *  # noqa: F403
from .utils import *  # noqa: F403  (Isaac Lab re-exports its prim and stage helpers from isaaclab.sim)
