"""rsl_rl agent configs of the G1 velocity tasks."""
