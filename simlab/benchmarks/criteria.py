"""When is a task solved? Each criterion plays a policy and says whether what it saw passes.

cartpole: |pole angle| < 0.2 rad in >= 95 % of the env-steps of 64 envs over 5 s.
humanoid, ant: the mean reward per env-step over the played window (falls and resets included)
stays at or above a stated threshold.
velocity tasks (Go2, Anymal): the base's planar velocity follows the command, mean error <= 0.25 m/s.
quadcopter: from 2 s into an episode (the flight to the goal), within 0.3 m of it in >= 75 % of the env-steps.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import torch

# Mean reward per env-step a played policy must keep. A first setting, not yet checked against
# played policies: docs/performance.md's GPU humanoid run ends at 7410 mean episode reward over
# 874-step episodes (about 8.5 per step); the ant uses the same reward terms. Override with
# --reward_threshold.
MEAN_REWARD_THRESHOLDS = {"Humanoid": 5.0, "Ant": 5.0}


def pole_angle_tracker(threshold: float) -> tuple[Callable[[Any, Any, Any], None], dict[str, int]]:
    """An ``on_step`` hook (for :func:`simlab.cli.play.rollout`) counting env-steps with
    |pole angle| below ``threshold``; returns the hook and its counts."""
    counts = {"inside": 0, "total": 0}
    joint: dict = {}

    def on_step(env, obs, actions) -> None:
        if not joint:
            for asset in env.scene.articulations.values():
                if "cart_to_pole" in asset.joint_names:
                    joint["asset"], joint["id"] = asset, asset.joint_names.index("cart_to_pole")
            if not joint:
                raise RuntimeError("No articulation with a 'cart_to_pole' joint in this task.")
        angle = joint["asset"].data.joint_pos[:, joint["id"]]
        angle = torch.remainder(angle + math.pi, 2 * math.pi) - math.pi
        counts["inside"] += int((angle.abs() < threshold).sum())
        counts["total"] += angle.numel()

    return on_step, counts


@dataclass
class Criterion:
    """What a played policy must show; ``judge`` turns a rollout into (score, passed)."""

    description: str
    make_hook: Callable[[], tuple[Callable | None, Any]]
    judge: Callable[[dict[str, float], Any], tuple[float, bool]]


def pole_upright(threshold: float = 0.2, fraction: float = 0.95) -> Criterion:
    def judge(result: dict[str, float], counts: dict[str, int]) -> tuple[float, bool]:
        inside = counts["inside"] / max(1, counts["total"])
        return inside, inside >= fraction

    return Criterion(
        f"|pole angle| < {threshold} rad in >= {fraction:.0%} of steps",
        lambda: pole_angle_tracker(threshold),
        judge,
    )


def mean_reward_at_least(threshold: float) -> Criterion:
    def judge(result: dict[str, float], _: Any) -> tuple[float, bool]:
        return result["mean_reward"], result["mean_reward"] >= threshold

    return Criterion(f"mean reward per env-step >= {threshold:g}", lambda: (None, None), judge)


def velocity_tracker() -> tuple[Callable[[Any, Any, Any], None], dict[str, float]]:
    """An ``on_step`` hook summing ``|v_xy command - v_xy|`` (base frame) over env-steps."""
    sums = {"error": 0.0, "total": 0}

    def on_step(env, obs, actions) -> None:
        base = env.unwrapped
        command = base.command_manager.get_command("base_velocity")
        velocity = base.scene["robot"].data.root_lin_vel_b
        sums["error"] += float(torch.linalg.norm(command[:, :2] - velocity[:, :2], dim=-1).sum())
        sums["total"] += command.shape[0]

    return on_step, sums


def tracks_velocity(max_error: float = 0.25) -> Criterion:
    def judge(result: dict[str, float], sums: dict[str, float]) -> tuple[float, bool]:
        error = sums["error"] / max(1, sums["total"])
        return error, error <= max_error

    return Criterion(f"mean |v_xy command - v_xy| <= {max_error} m/s", velocity_tracker, judge)


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


def criterion_for(task: str, reward_threshold: float | None = None) -> Criterion:
    """The criterion of ``task`` (a Gymnasium id); ``reward_threshold`` replaces the stated one."""
    if reward_threshold is not None:
        return mean_reward_at_least(reward_threshold)
    if "Cartpole" in task:
        return pole_upright()
    if "Velocity-" in task:
        return tracks_velocity()
    if "Quadcopter" in task:
        return reaches_goal()
    for robot, threshold in MEAN_REWARD_THRESHOLDS.items():
        if robot in task:
            return mean_reward_at_least(threshold)
    raise ValueError(
        f"No solve criterion for {task}: the cartpole, velocity, quadcopter and {list(MEAN_REWARD_THRESHOLDS)}"
        " tasks have one; "
        "give --reward_threshold R to judge by the mean reward per env-step."
    )
