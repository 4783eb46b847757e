"""Tasks of the direct workflow (Isaac Lab's ``isaaclab_tasks.direct``)."""
