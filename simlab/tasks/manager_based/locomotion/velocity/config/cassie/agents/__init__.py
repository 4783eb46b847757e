"""rsl_rl agent configs of the Cassie velocity tasks."""
