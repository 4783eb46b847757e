# Isaac Lab 3.0's isaaclab_tasks/core/cartpole (release 3.0 text), ported by the 3.0 mapping of docs/porting_3.md:
# isaaclab.assets / .envs / .scene / .utils.math -> simlab.v3.*, the other isaaclab.* modules -> simlab.*,
# isaaclab_assets -> simlab.v3.robots, isaaclab_tasks.core.cartpole -> this package. Each file says which lines differ.
