"""Interpolation of sampled functions (Isaac Lab's ``utils.interpolation``)."""

from .linear_interpolation import LinearInterpolation

__all__ = ["LinearInterpolation"]
