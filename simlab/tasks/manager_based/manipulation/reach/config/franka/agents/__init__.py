"""Agent configs for the Franka reach task."""
