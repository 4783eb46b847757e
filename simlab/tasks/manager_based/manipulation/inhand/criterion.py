"""The manager-based in-hand task's criterion: on average >= 5 goal orientations reached per episode.

The goal command counts the goals reached in each episode (its ``consecutive_success`` metric) and
keeps the count of every episode that ends (``episode_successes``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from simlab.tasks.direct.inhand_manipulation.criterion import reorients_cube as _reorients_cube
from simlab.tasks.utils.criteria import Criterion


def command_success_tracker(command_name: str = "object_pose") -> tuple[Callable[[Any, Any, Any], None], dict]:
    """An ``on_step`` hook summing the goals reached in each episode that ends."""
    sums = {"successes": 0.0, "episodes": 0}

    def on_step(env, obs, actions) -> None:
        finished = env.reset_buf  # the envs whose episode ended in this step (already reset)
        if not bool(finished.any()):
            return
        counts = env.command_manager.get_term(command_name).episode_successes
        sums["successes"] += float(counts[finished].sum())
        sums["episodes"] += int(finished.sum())

    return on_step, sums


def reorients_cube(min_successes: float = 5.0) -> Criterion:
    return _reorients_cube(min_successes, episode_s=20.0, tracker=command_success_tracker)
