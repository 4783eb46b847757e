"""Sensors read from the simulation each step: contact forces, frames, IMUs."""

from .sensor_base import SensorBase, SensorBaseCfg
