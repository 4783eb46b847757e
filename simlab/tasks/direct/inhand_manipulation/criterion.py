"""The in-hand tasks' criterion: on average >= 5 goal orientations reached per episode.

Each goal the cube reaches is replaced by a new one at once, so an episode's count of successes is
how many orientations in a row the policy turned the cube to before the episode ended (a fall or the
time limit). The env keeps that count for every episode that ends (``episode_successes``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from simlab.tasks.utils.criteria import Criterion


def episode_success_tracker() -> tuple[Callable[[Any, Any, Any], None], dict[str, float]]:
    """An ``on_step`` hook summing the goals reached in each episode that ends."""
    sums = {"successes": 0.0, "episodes": 0}

    def on_step(env, obs, actions) -> None:
        finished = env.reset_buf  # the envs whose episode ended in this step (already reset)
        if not bool(finished.any()):
            return
        sums["successes"] += float(env.episode_successes[finished].sum())
        sums["episodes"] += int(finished.sum())

    return on_step, sums


def reorients_cube(
    min_successes: float = 5.0,
    episode_s: float = 10.0,
    tracker: Callable[[], tuple[Callable[[Any, Any, Any], None], dict[str, float]]] = episode_success_tracker,
) -> Criterion:
    """Judge by the mean count of goals reached per finished episode; ``tracker`` makes the hook that
    sums them (``{"successes": ..., "episodes": ...}``)."""

    def judge(result: dict[str, float], sums: dict[str, float]) -> tuple[float, bool]:
        if not sums["episodes"]:
            return 0.0, False
        mean = sums["successes"] / sums["episodes"]
        return mean, mean >= min_successes

    return Criterion(
        f"on average >= {min_successes:g} goal orientations reached per episode (score: the mean)",
        tracker,
        judge,
        min_seconds=episode_s + 0.5,
    )
