"""Unitree Go1 velocity tracking, flat and rough (Isaac Lab's ``Isaac-Velocity-*-Unitree-Go1-v0``)."""

from ..register import register_velocity_tasks

register_velocity_tasks(__name__, "Unitree-Go1")
