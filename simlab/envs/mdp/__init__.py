"""The MDP term library: actions, observations, rewards, terminations, events, commands and
curricula, with Isaac Lab's names (``import simlab.envs.mdp as mdp``)."""

from .actions import *  # noqa: F403
from .commands import *  # noqa: F403
from .curriculums import *  # noqa: F403
from .events import *  # noqa: F403
from .image_features import image_features
from .observations import *  # noqa: F403
from .recorders import *  # noqa: F403
from .rewards import *  # noqa: F403
from .terminations import *  # noqa: F403
