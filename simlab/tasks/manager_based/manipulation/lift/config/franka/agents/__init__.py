"""Agent configs for the Franka lift task."""
