"""The loco-manipulation tracking tasks' robots."""
