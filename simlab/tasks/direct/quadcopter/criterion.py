"""The quadcopter's criterion: from 2 s into an episode (the flight to the goal), within 0.3 m of it in
>= 75 % of the env-steps."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import torch

from simlab.tasks.utils.criteria import Criterion


def goal_distance_tracker(
    radius: float, settle_seconds: float
) -> tuple[Callable[[Any, Any, Any], None], dict[str, int]]:
    """An ``on_step`` hook counting env-steps, ``settle_seconds`` or more after the quadcopter's start
    (the play's first step or its last reset: the flight to the goal), within ``radius`` of its goal.

    The time is counted here: the task starts its episodes at random lengths.
    """
    counts = {"inside": 0, "total": 0}
    flying: dict[str, torch.Tensor] = {}

    def on_step(env, obs, actions) -> None:
        base = env.unwrapped
        steps = flying.setdefault("steps", torch.zeros(base.num_envs, dtype=torch.long, device=base.device))
        steps.add_(1)
        settled = steps >= math.ceil(settle_seconds / base.step_dt - 1e-6)
        steps.masked_fill_(base.reset_buf, 0)  # restarted: the next step is its first
        distance = torch.linalg.norm(base._desired_pos_w - base._robot.data.root_pos_w, dim=1)
        counts["inside"] += int((settled & (distance < radius)).sum())
        counts["total"] += int(settled.sum())

    return on_step, counts


def reaches_goal(radius: float = 0.3, fraction: float = 0.75, settle_seconds: float = 2.0) -> Criterion:
    def judge(result: dict[str, float], counts: dict[str, int]) -> tuple[float, bool]:
        inside = counts["inside"] / max(1, counts["total"])
        return inside, counts["total"] > 0 and inside >= fraction

    return Criterion(
        f"from {settle_seconds:g} s into an episode, within {radius} m of the goal in >= {fraction:.0%} of steps",
        lambda: goal_distance_tracker(radius, settle_seconds),
        judge,
    )
