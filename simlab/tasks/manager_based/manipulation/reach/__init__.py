"""Reach an end-effector pose (Isaac Lab's ``manipulation/reach``); robots in ``config/``."""
