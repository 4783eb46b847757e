"""Robots for the deployed reach task."""
