"""The lift task's MDP terms: simlab's library plus the object's observation, rewards and terminations."""

from simlab.envs.mdp import *  # noqa: F403

from .observations import *  # noqa: F403
from .rewards import *  # noqa: F403
from .terminations import *  # noqa: F403
