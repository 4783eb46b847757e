"""Unitree A1 velocity tracking, flat and rough (Isaac Lab's ``Isaac-Velocity-*-Unitree-A1-v0``)."""

from ..register import register_velocity_tasks

register_velocity_tasks(__name__, "Unitree-A1")
