"""The Franka lift tasks' criterion: >= 80 % of the episodes end with the cube within 5 cm of its commanded
position."""

from __future__ import annotations

from functools import partial
from typing import Any

import torch

from simlab.tasks.utils.criteria import Criterion, episode_end_tracker, episodes_succeed


def cube_near_goal(env: Any, tolerance_m: float) -> torch.Tensor:
    from simlab.tasks.manager_based.manipulation.lift import mdp

    return mdp.object_reached_goal(env, "object_pose", threshold=tolerance_m)


def cube_reaches_goal(tolerance_m: float = 0.05) -> Criterion:
    hook = partial(episode_end_tracker, partial(cube_near_goal, tolerance_m=tolerance_m))
    return episodes_succeed(f"the cube within {tolerance_m} m of its goal", hook, episode_s=5.0)
