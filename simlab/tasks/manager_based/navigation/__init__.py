"""Navigation tasks (Isaac Lab's ``isaaclab_tasks.manager_based.navigation``): a high-level policy
steers a frozen low-level locomotion policy to a goal pose."""
