"""Sensors read from the simulation each step: contact forces, ray casts (height scans), IMUs, frames, cameras."""

from .camera import (
    DATA_TYPES,
    Camera,
    CameraCfg,
    CameraData,
    TiledCamera,
    TiledCameraCfg,
    save_images_to_file,
    tile_images,
)
from .contact_sensor import ContactSensor, ContactSensorCfg, ContactSensorData
from .frame_transformer import FrameTransformer, FrameTransformerCfg, FrameTransformerData, OffsetCfg
from .imu import Imu, ImuCfg, ImuData
from .joint_wrench import JointWrenchSensor, JointWrenchSensorCfg, JointWrenchSensorData
from .ray_caster import RayCaster, RayCasterCamera, RayCasterCameraCfg, RayCasterCfg, RayCasterData, patterns
from .sensor_base import SensorBase, SensorBaseCfg

__all__ = [
    "DATA_TYPES",
    "Camera",
    "CameraCfg",
    "CameraData",
    "ContactSensor",
    "ContactSensorCfg",
    "ContactSensorData",
    "FrameTransformer",
    "FrameTransformerCfg",
    "FrameTransformerData",
    "Imu",
    "ImuCfg",
    "ImuData",
    "JointWrenchSensor",
    "JointWrenchSensorCfg",
    "JointWrenchSensorData",
    "OffsetCfg",
    "RayCaster",
    "RayCasterCamera",
    "RayCasterCameraCfg",
    "RayCasterCfg",
    "RayCasterData",
    "SensorBase",
    "SensorBaseCfg",
    "TiledCamera",
    "TiledCameraCfg",
    "patterns",
    "save_images_to_file",
    "tile_images",
]
