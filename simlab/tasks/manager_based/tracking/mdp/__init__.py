"""The tracking tasks' MDP terms: simlab's library, and the motion command with its rewards,
observations and terminations."""

from simlab.envs.mdp import *  # noqa: F403

from .commands import MotionCommand, MotionCommandCfg  # noqa: F401
from .observations import *  # noqa: F403
from .rewards import *  # noqa: F403
from .terminations import *  # noqa: F403
