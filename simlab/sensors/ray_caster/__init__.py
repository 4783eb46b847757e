"""The ray caster (Isaac Lab's ``isaaclab.sensors.ray_caster``)."""

from . import patterns
from .ray_caster import RayCaster
from .ray_caster_cfg import RayCasterCfg
from .ray_caster_data import RayCasterData

__all__ = ["RayCaster", "RayCasterCfg", "RayCasterData", "patterns"]
