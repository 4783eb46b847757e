"""Agent configs for the deployed UR10e reach task."""
