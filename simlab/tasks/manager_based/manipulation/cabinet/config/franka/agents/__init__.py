"""Agent configs of the Franka cabinet task."""
