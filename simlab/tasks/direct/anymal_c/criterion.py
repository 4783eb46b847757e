"""The direct ANYmal-C task's criterion: the velocity tasks' bar (mean |v_xy command - v_xy| <= 0.25 m/s,
base frame), read from the task's own command buffer (a direct task has no command manager)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import torch

from simlab.tasks.utils.criteria import Criterion


def velocity_tracker() -> tuple[Callable[[Any, Any, Any], None], dict[str, float]]:
    """An ``on_step`` hook summing ``|v_xy command - v_xy|`` over env-steps."""
    sums = {"error": 0.0, "total": 0}

    def on_step(env, obs, actions) -> None:
        base = env.unwrapped
        command, velocity = base._commands[:, :2], base._robot.data.root_lin_vel_b[:, :2]
        sums["error"] += float(torch.linalg.norm(command - velocity, dim=-1).sum())
        sums["total"] += command.shape[0]

    return on_step, sums


def tracks_velocity(max_error: float = 0.25) -> Criterion:
    def judge(result: dict[str, float], sums: dict[str, float]) -> tuple[float, bool]:
        error = sums["error"] / max(1, sums["total"])
        return error, error <= max_error

    return Criterion(f"mean |v_xy command - v_xy| <= {max_error} m/s", velocity_tracker, judge)
