"""Per-robot tracking tasks."""
