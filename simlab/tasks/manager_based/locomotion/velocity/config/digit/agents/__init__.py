"""rsl_rl agent configs of the Digit velocity tasks."""
