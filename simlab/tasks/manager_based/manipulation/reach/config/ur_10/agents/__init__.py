"""Agent configs for the UR10 reach task."""
