"""Agent configs for the two-arm OpenArm reach task."""
