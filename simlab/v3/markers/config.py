"""``isaaclab.markers.config`` of Isaac Lab 3.0: simlab's marker configs (they hold no orientation)."""

from simlab.markers.config import *  # noqa: F403
