"""Stack cubes (Isaac Lab's ``manipulation/stack``): the Franka arm stacks cube 2 on cube 1 and cube 3
on cube 2. A task for demonstrations and imitation learning: it has no rewards, a ``subtask_terms``
observation group (grasp_1, stack_1, grasp_2) that demonstration tools read, and ends an episode when
the cubes are stacked; robots in ``config/``."""
