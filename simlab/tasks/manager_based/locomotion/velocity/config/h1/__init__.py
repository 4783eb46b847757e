"""Unitree H1 velocity tracking, flat and rough (Isaac Lab's ``Isaac-Velocity-*-H1-v0``).

Solved when a played policy tracks the commands (planar speed and yaw rate, few falls); on rough
ground, when the terrain curriculum keeps the robots at level 3 or higher (the Play variant, without
the curriculum, is judged by tracking).
"""

from ..register import register_velocity_tasks

register_velocity_tasks(__name__, "H1", biped=True)
