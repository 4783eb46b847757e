"""Navigation task configurations, one folder per robot."""
