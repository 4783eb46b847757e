"""Sensors read from the simulation each step: contact forces, ray casts (height scans), IMUs."""

from .contact_sensor import ContactSensor, ContactSensorCfg, ContactSensorData
from .imu import Imu, ImuCfg, ImuData
from .ray_caster import RayCaster, RayCasterCfg, RayCasterData, patterns
from .sensor_base import SensorBase, SensorBaseCfg

__all__ = [
    "ContactSensor",
    "ContactSensorCfg",
    "ContactSensorData",
    "Imu",
    "ImuCfg",
    "ImuData",
    "RayCaster",
    "RayCasterCfg",
    "RayCasterData",
    "SensorBase",
    "SensorBaseCfg",
    "patterns",
]
