"""Boston Dynamics Spot velocity tracking on Isaac Lab's cobblestone road (``Isaac-Velocity-Flat-Spot-v0``)."""

from ..register import register_velocity_tasks

register_velocity_tasks(__name__, "Spot", terrains=("Flat",))
