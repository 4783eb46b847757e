"""Helpers of the environments: Gymnasium spaces from config specs, multi-agent conversion."""

from .spaces import sample_space, spec_to_gym_space

__all__ = ["sample_space", "spec_to_gym_space"]
