# Isaac Lab 3.0's isaaclab_tasks lift task, its mdp observation ported by the 3.0 mapping of docs/porting_3.md.
