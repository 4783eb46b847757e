"""The cart double pendulum's criterion: pole and pendulum both within 0.2 rad of upright in >= 75 % of the
env-steps (episodes start up to 0.79 rad off, so the first moments of each are spent swinging them up)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from simlab.tasks.utils.criteria import Criterion, wrapped_angle


def double_pendulum_tracker(threshold: float) -> tuple[Callable[[Any, Any, Any], None], dict[str, int]]:
    """An ``on_step`` hook counting env-steps with the pole and the pendulum (its angle in the world:
    pole + pendulum joint) both within ``threshold`` of upright."""
    counts = {"inside": 0, "total": 0}

    def on_step(env, obs, actions) -> None:
        robot = env.scene["robot"]  # the scene, not env.robot: training wraps the two agents as one
        pole = robot.data.joint_pos[:, robot.joint_names.index("cart_to_pole")]
        pendulum = pole + robot.data.joint_pos[:, robot.joint_names.index("pole_to_pendulum")]
        upright = (wrapped_angle(pole).abs() < threshold) & (wrapped_angle(pendulum).abs() < threshold)
        counts["inside"] += int(upright.sum())
        counts["total"] += upright.numel()

    return on_step, counts


def both_poles_upright(threshold: float = 0.2, fraction: float = 0.75) -> Criterion:
    def judge(result: dict[str, float], counts: dict[str, int]) -> tuple[float, bool]:
        inside = counts["inside"] / max(1, counts["total"])
        return inside, inside >= fraction

    return Criterion(
        f"pole and pendulum both within {threshold} rad of upright in >= {fraction:.0%} of steps",
        lambda: double_pendulum_tracker(threshold),
        judge,
    )
