"""rsl_rl agent configs of the G1 tracking task."""
