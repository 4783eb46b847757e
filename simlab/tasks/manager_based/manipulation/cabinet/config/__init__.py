"""Robots for the cabinet task."""
