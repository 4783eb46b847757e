"""ANYmal-D velocity tracking, flat and rough (Isaac Lab's ``Isaac-Velocity-*-Anymal-D-v0``); on flat ground
also student-teacher distillation, as Isaac Lab registers it."""

from ..register import register_velocity_tasks

register_velocity_tasks(__name__, "Anymal-D", distillation=("Flat",))
