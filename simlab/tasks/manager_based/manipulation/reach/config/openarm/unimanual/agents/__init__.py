"""Agent configs for the one-arm OpenArm reach task."""
