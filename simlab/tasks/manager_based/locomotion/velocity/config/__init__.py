"""Per-robot velocity-tracking tasks."""
