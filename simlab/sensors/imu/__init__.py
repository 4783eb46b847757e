"""The inertial measurement unit (Isaac Lab's ``isaaclab.sensors.imu``)."""

from .imu import Imu, ImuData
from .imu_cfg import ImuCfg

__all__ = ["Imu", "ImuCfg", "ImuData"]
