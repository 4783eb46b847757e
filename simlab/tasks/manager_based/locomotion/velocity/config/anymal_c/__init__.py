"""ANYmal-C velocity tracking, flat and rough (Isaac Lab's ``Isaac-Velocity-*-Anymal-C-v0``)."""

from ..register import register_velocity_tasks

register_velocity_tasks(__name__, "Anymal-C")
