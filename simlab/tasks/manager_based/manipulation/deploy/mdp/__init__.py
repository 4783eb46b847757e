"""The deployed tasks' MDP terms: simlab's library plus the keypoint pose-tracking rewards."""

from simlab.envs.mdp import *  # noqa: F403

from .rewards import *  # noqa: F403
