"""Agent configs of this task, one per RL library."""
