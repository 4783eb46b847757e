"""Robots for the lift task."""
