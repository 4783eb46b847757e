"""rsl_rl agent configs of the H1 velocity tasks."""
