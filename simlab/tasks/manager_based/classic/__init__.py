"""Classic control tasks, manager-based."""
