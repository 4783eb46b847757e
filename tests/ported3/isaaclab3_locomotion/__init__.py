# Isaac Lab 3.0's isaaclab_tasks/core/locomotion (ant and humanoid), its mdp terms ported by the 3.0 mapping of
# docs/porting_3.md: isaaclab.utils.math -> simlab.v3.utils.math ((x, y, z, w)), the other isaaclab.* -> simlab.*.
