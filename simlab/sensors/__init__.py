"""Sensors read from the simulation each step: contact forces, frames, IMUs."""

from .contact_sensor import ContactSensor, ContactSensorCfg, ContactSensorData
from .frame_transformer import FrameTransformer, FrameTransformerCfg, FrameTransformerData, OffsetCfg
from .sensor_base import SensorBase, SensorBaseCfg
