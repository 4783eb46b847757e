"""The Franka drawer tasks' criterion: >= 80 % of the episodes end with the top drawer open >= 20 cm."""

from __future__ import annotations

from functools import partial
from typing import Any

import torch

from simlab.tasks.utils.criteria import Criterion, episode_end_tracker, episodes_succeed


def drawer_open(env: Any, min_opening_m: float) -> torch.Tensor:
    cabinet = env.scene["cabinet"]
    return cabinet.data.joint_pos[:, cabinet.joint_names.index("drawer_top_joint")] >= min_opening_m


def drawer_opens(min_opening_m: float = 0.2) -> Criterion:
    hook = partial(episode_end_tracker, partial(drawer_open, min_opening_m=min_opening_m))
    return episodes_succeed(f"the top drawer open >= {min_opening_m} m", hook, episode_s=8.0)
