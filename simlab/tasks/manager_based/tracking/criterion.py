"""The tracking tasks' criterion: over a play of the clip, the tracked bodies stay within 10 cm of the
clip on average (positions relative to the anchor, :class:`MotionCommand`'s ``error_body_pos``), and
no robot falls (an anchor or end-effector termination).

The play is the clip's, as the -Play task and mjlab's play it: every env starts at the clip's first
frame in its state (no start-time sampling where the policy fails most, no start-state noise), without
pushes or observation noise. Judged in training's env instead, every robot would have to survive
pushes of up to 0.5 m/s every 1-3 s from the clip's hardest moments, with no fall allowed."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from simlab.tasks.utils.criteria import Criterion

MAX_BODY_ERROR = 0.10  # m

_ZERO_RANGES = tuple(
    f"env.commands.motion.{ranges}.{axis}=[0.0,0.0]"
    for ranges in ("pose_range", "velocity_range")
    for axis in ("x", "y", "z", "roll", "pitch", "yaw")
)
CLIP_PLAY = (
    "env.commands.motion.adaptive_sampling=false",
    "env.commands.motion.joint_position_range=[0.0,0.0]",
    *_ZERO_RANGES,
    "env.events.push_robot=null",
    "env.observations.policy.enable_corruption=false",
)
"""The overrides that make training's env play the clip through (the -Play task's settings)."""


def body_error_tracker() -> tuple[Callable[[Any, Any, Any], None], dict[str, float]]:
    sums = {"error": 0.0, "samples": 0, "falls": 0}

    def on_step(env, obs, actions) -> None:
        base = env.unwrapped
        error = base.command_manager.get_term("motion").metrics["error_body_pos"]
        sums["error"] += float(error.sum())
        sums["samples"] += error.numel()
        sums["falls"] += int(base.termination_manager.terminated.sum())

    return on_step, sums


def tracks_clip(max_error: float = MAX_BODY_ERROR, seconds: float = 10.0) -> Criterion:
    def judge(result: dict[str, float], sums: dict[str, float]) -> tuple[float, bool]:
        error = sums["error"] / max(1, sums["samples"])
        return error, error < max_error and sums["falls"] == 0

    return Criterion(
        f"mean anchor-relative body position error < {max_error * 100:g} cm, no falls",
        body_error_tracker,
        judge,
        min_seconds=seconds,
        play_overrides=CLIP_PLAY,
    )
