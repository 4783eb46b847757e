# Isaac Lab 3.0's isaaclab_tasks/core/cartpole/mdp: Isaac Lab's env mdp terms (simlab.envs.mdp, as mapped)
# and the task's own rewards (rewards.py, ported).

from simlab.v3.envs.mdp import *  # noqa: F401, F403

from .rewards import *  # noqa: F401, F403
