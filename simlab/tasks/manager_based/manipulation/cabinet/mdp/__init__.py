"""The cabinet task's MDP terms: simlab's library plus the drawer's observations and rewards."""

from simlab.envs.mdp import *  # noqa: F403

from .observations import *  # noqa: F403
from .rewards import *  # noqa: F403
