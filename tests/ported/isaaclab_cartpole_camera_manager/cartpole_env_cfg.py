# Isaac Lab's sibling module, at its mapped path in simlab.
from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import *  # noqa: F403
