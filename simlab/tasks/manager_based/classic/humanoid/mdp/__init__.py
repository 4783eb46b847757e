"""MDP terms of the classic locomotion tasks (humanoid and ant share them, as in Isaac Lab)."""

from simlab.envs.mdp import *  # noqa: F403

from .observations import *  # noqa: F403
from .rewards import *  # noqa: F403
