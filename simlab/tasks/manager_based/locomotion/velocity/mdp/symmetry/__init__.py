"""Symmetry augmentation of the velocity tasks' data for rsl_rl's PPO (Isaac Lab's ``mdp.symmetry``)."""

from . import anymal

__all__ = ["anymal"]
