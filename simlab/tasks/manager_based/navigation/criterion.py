"""The navigation task's criterion: >= 80 % of the episodes end with the base within 0.5 m of the goal
and within 0.5 rad of its heading, not fallen.

Isaac Lab's rewards pull the base to the goal on two scales (``tanh(d / 2 m)`` and ``tanh(d / 0.2 m)``)
and penalize the heading error linearly; 0.5 m (about the base's half length) and 0.5 rad are where
the fine reward still pays a tenth of its maximum, a goal reached, not a goal approached."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import torch

from simlab.tasks.utils.criteria import Criterion, episodes_succeed

MAX_POSITION_ERROR = 0.5  # m
MAX_HEADING_ERROR = 0.5  # rad
POSE_COMMAND_OBS = slice(6, 10)  # the policy group: base_lin_vel (3), projected_gravity (3), pose_command (4)


def goal_reached(final_policy_obs: torch.Tensor) -> torch.Tensor:
    """(num_envs,) bool: the pose command in a final observation says the goal is reached."""
    command = final_policy_obs[:, POSE_COMMAND_OBS]
    return (torch.linalg.norm(command[:, :2], dim=1) < MAX_POSITION_ERROR) & (command[:, 3].abs() < MAX_HEADING_ERROR)


def goal_tracker() -> tuple[Callable[[Any, Any, Any], None], dict[str, int]]:
    """An ``on_step`` hook judging each finished episode by its final observation (before the reset):
    a time-out at the goal succeeds, a fall fails."""
    counts = {"success": 0, "episodes": 0}

    def on_step(env, obs, actions) -> None:
        base = env.unwrapped
        finished = base.reset_buf
        if not bool(finished.any()):
            return
        reached = goal_reached(base.extras["final_obs"]["policy"]) & ~base.termination_manager.terminated
        counts["success"] += int((finished & reached).sum())
        counts["episodes"] += int(finished.sum())

    return on_step, counts


def reaches_goal_pose() -> Criterion:
    return episodes_succeed(
        f"the base within {MAX_POSITION_ERROR} m and {MAX_HEADING_ERROR} rad of the goal pose, not fallen",
        goal_tracker,
        episode_s=8.0,
    )
