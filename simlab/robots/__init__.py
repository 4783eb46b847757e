"""Robot configurations and their MJCF models (``simlab.robots.<robot>``)."""

from .cartpole import CARTPOLE_CFG
