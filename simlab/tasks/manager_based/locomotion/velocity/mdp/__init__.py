"""The velocity tasks' MDP terms: simlab's library (which holds the locomotion terms too)."""

from simlab.envs.mdp import *  # noqa: F403
