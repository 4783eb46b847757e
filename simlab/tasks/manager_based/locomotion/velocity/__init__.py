"""Velocity tracking on flat and rough terrain (Isaac Lab's ``Isaac-Velocity-*`` tasks)."""
