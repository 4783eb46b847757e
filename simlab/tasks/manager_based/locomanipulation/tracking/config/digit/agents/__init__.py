"""rsl_rl agent config of the Digit loco-manipulation task."""
