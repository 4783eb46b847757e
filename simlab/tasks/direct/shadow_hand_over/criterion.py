"""The handover's criterion: the ball caught in >= 80 % of the episodes that end.

An episode catches the ball when the ball comes within ``catch_radius`` of the goal above the left
palm and has not fallen when the episode ends; the env records it per env (``episode_caught``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from simlab.tasks.utils.criteria import Criterion


def catch_tracker() -> tuple[Callable[[Any, Any, Any], None], dict[str, int]]:
    """An ``on_step`` hook counting the episodes that end and those of them that caught the ball."""
    counts = {"caught": 0, "episodes": 0}

    def on_step(env, obs, actions) -> None:
        env = env.unwrapped
        # PPO trains and plays the two hands as one agent (multi_agent_to_single_agent): that face keeps
        # the two-agent env, which records the catches, as .env
        env = getattr(env, "env", env)
        finished = env.reset_buf  # the envs whose episode ended in this step (already reset)
        if not bool(finished.any()):
            return
        counts["caught"] += int(env.episode_caught[finished].sum())
        counts["episodes"] += int(finished.sum())

    return on_step, counts


def ball_caught(fraction: float = 0.8, episode_s: float = 7.5) -> Criterion:
    def judge(result: dict[str, float], counts: dict[str, int]) -> tuple[float, bool]:
        if not counts["episodes"]:
            return 0.0, False
        caught = counts["caught"] / counts["episodes"]
        return caught, caught >= fraction

    return Criterion(
        f"the ball caught (within the goal zone, not dropped) in >= {fraction:.0%} of episodes (score: the share)",
        catch_tracker,
        judge,
        min_seconds=episode_s + 0.5,
    )
