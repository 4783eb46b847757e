"""Robots for the stack task."""
