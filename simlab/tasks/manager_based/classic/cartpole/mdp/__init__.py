"""The cartpole's MDP terms: simlab's library plus the task's own reward."""

from simlab.envs.mdp import *  # noqa: F403

from .rewards import *  # noqa: F403
