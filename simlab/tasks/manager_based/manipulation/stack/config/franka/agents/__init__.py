"""Agent configs for the Franka stack task: behaviour cloning from demonstrations."""
