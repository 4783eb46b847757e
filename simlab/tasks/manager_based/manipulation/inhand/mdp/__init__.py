"""The in-hand task's MDP terms: simlab's library plus the goal-orientation command and its terms."""

from simlab.envs.mdp import *  # noqa: F403

from .commands import *  # noqa: F403
from .events import *  # noqa: F403
from .observations import *  # noqa: F403
from .rewards import *  # noqa: F403
from .terminations import *  # noqa: F403
