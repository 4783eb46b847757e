"""Legged locomotion tasks (Isaac Lab's ``isaaclab_tasks.manager_based.locomotion``)."""
