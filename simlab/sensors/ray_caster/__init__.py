"""The ray caster (Isaac Lab's ``isaaclab.sensors.ray_caster``) and the ray-cast camera."""

from . import patterns
from .ray_caster import RayCaster
from .ray_caster_camera import RayCasterCamera
from .ray_caster_camera_cfg import RayCasterCameraCfg
from .ray_caster_cfg import RayCasterCfg
from .ray_caster_data import RayCasterData

__all__ = ["RayCaster", "RayCasterCamera", "RayCasterCameraCfg", "RayCasterCfg", "RayCasterData", "patterns"]
