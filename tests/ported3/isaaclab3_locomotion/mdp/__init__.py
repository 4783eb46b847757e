# Isaac Lab 3.0's isaaclab_tasks/core/locomotion/mdp: Isaac Lab's env mdp terms (simlab.v3.envs.mdp, as mapped)
# and the ant and humanoid terms (observations.py, rewards.py, ported).

from simlab.v3.envs.mdp import *  # noqa: F401, F403

from .later_terms import *  # noqa: F401, F403
from .observations import *  # noqa: F401, F403
from .rewards import *  # noqa: F401, F403
