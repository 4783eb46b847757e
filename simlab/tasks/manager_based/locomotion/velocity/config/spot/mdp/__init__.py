"""Spot's own velocity-task terms (Isaac Lab's ``config/spot/mdp``): a trotting-gait reward, foot
clearance, air-time variance and the other rewards of Spot's flat task, and its joint reset."""

from .events import *  # noqa: F403
from .rewards import *  # noqa: F403
