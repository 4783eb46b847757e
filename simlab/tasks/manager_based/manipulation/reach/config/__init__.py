"""Robots for the reach task."""
