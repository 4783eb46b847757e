"""Reach a pose with a policy made for a real robot (Isaac Lab's ``deploy/reach``); robots in ``config/``."""
