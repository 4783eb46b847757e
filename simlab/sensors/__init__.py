"""Sensors read from the simulation each step: contact forces, frames, IMUs, cameras."""

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
from .sensor_base import SensorBase, SensorBaseCfg
