"""Whole-body motion tracking: a humanoid follows a clip of joint and body states (mjlab's and Isaac Lab's
G1 tracking tasks)."""
