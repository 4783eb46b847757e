"""Agent configurations of the ANYmal-C navigation task."""
