"""Agent configs of the spaces showcase (skrl only, as Isaac Lab has them)."""
