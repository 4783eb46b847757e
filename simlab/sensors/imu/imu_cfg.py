"""Configuration of the IMU (Isaac Lab's ``ImuCfg``)."""

from __future__ import annotations

from simlab.sensors.sensor_base import SensorBaseCfg
from simlab.utils import configclass

from .imu import Imu


@configclass
class ImuCfg(SensorBaseCfg):
    """An IMU on one body (``prim_path``, e.g. ``{ENV_REGEX_NS}/Robot/base``)."""

    @configclass
    class OffsetCfg:
        """Pose of the IMU in the body's frame."""

        pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
        rot: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
        """(w, x, y, z)."""

    class_type: type = Imu
    offset: OffsetCfg = OffsetCfg()
    gravity_bias: tuple[float, float, float] = (0.0, 0.0, 9.81)
    """Added to the IMU's acceleration in the world frame before it is turned into the IMU frame:
    the default makes ``lin_acc_b`` read +9.81 m/s^2 up at rest, as a real accelerometer does."""
    visualizer_cfg: object | None = None
