"""ANYmal-B velocity tracking, flat and rough (Isaac Lab's ``Isaac-Velocity-*-Anymal-B-v0``)."""

from ..register import register_velocity_tasks

register_velocity_tasks(__name__, "Anymal-B", symmetry=True)
