"""Agent configs for the deployed Rizon 4s reach task."""
