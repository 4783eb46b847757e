"""When is a task solved? Each criterion plays a policy and says whether what it saw passes.

cartpole: |pole angle| < 0.2 rad in >= 95 % of the env-steps of 64 envs over 5 s.
humanoid, ant (direct and manager-based): the torso's mean speed towards the target (+x, where the
tasks' target lies 1 km away) over the played window of 64 envs for 5 s, falls and resets included,
is at least a stated speed. A speed, not a reward: the manager-based tasks' rewards are scaled by the
step time and the direct ones' are not, so one reward threshold cannot serve both.
velocity tasks (Go2, Anymal): the base's planar velocity follows the command, mean error <= 0.25 m/s.
quadcopter: from 2 s into an episode (the flight to the goal), within 0.3 m of it in >= 75 % of the env-steps.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import torch

# Mean torso speed towards the target [m/s] a played policy must keep. Measured on the CPU (64 envs,
# 5 s): untrained policies of Ant-v0 and Humanoid-v0 -0.03 and 0.03 m/s; the shipped Ant-Direct-v0
# and Humanoid-Direct-v0 policies 7.4 and 3.0 m/s.
FORWARD_SPEED_THRESHOLDS = {"Humanoid": 1.0, "Ant": 1.0}


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


def forward_speed_tracker() -> tuple[Callable[[Any, Any, Any], None], dict[str, float]]:
    """An ``on_step`` hook summing the root's world-frame x velocity (towards the target) over env-steps."""
    sums = {"speed": 0.0, "total": 0}

    def on_step(env, obs, actions) -> None:
        velocity = env.unwrapped.scene["robot"].data.root_lin_vel_w
        sums["speed"] += float(velocity[:, 0].sum())
        sums["total"] += velocity.shape[0]

    return on_step, sums


def runs_forward(min_speed: float) -> Criterion:
    def judge(result: dict[str, float], sums: dict[str, float]) -> tuple[float, bool]:
        speed = sums["speed"] / max(1, sums["total"])
        return speed, sums["total"] > 0 and speed >= min_speed

    return Criterion(f"mean torso speed towards the target >= {min_speed:g} m/s", forward_speed_tracker, judge)


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
    for robot, min_speed in FORWARD_SPEED_THRESHOLDS.items():
        if robot in task and "AMP" not in task:  # the AMP humanoids imitate a clip (a dance goes nowhere)
            return runs_forward(min_speed)
    raise ValueError(
        f"No solve criterion for {task}: the cartpole, velocity, quadcopter and {list(FORWARD_SPEED_THRESHOLDS)}"
        " tasks have one (the AMP humanoids have none); "
        "give --reward_threshold R to judge by the mean reward per env-step."
    )
