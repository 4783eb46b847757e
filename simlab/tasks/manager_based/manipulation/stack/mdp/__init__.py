"""The stack task's MDP terms: simlab's library plus the cubes' observations, the subtask signals, the
stacked termination and the reset events that place the cubes apart."""

from simlab.envs.mdp import *  # noqa: F403

from .franka_stack_events import *  # noqa: F403
from .observations import *  # noqa: F403
from .terminations import *  # noqa: F403
