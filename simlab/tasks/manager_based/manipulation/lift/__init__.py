"""Lift a cube to a commanded position (Isaac Lab's ``manipulation/lift``); robots in ``config/``."""
