from simlab.v3.envs.mdp import *  # noqa: F401, F403

from .observations import *  # noqa: F401, F403
