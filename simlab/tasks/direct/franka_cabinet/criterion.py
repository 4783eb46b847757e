"""The direct Franka cabinet's criterion: >= 80 % of the episodes end with the top drawer open >= 20 cm."""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from typing import Any

from simlab.tasks.utils.criteria import Criterion, episodes_succeed


def direct_cabinet_tracker(min_opening_m: float) -> tuple[Callable[[Any, Any, Any], None], dict[str, int]]:
    """An ``on_step`` hook for the direct cabinet: each finished episode's drawer opening, read from its
    final observation (an episode that pulls the drawer past 39 cm ends there, open)."""
    counts = {"success": 0, "episodes": 0}

    def on_step(env, obs, actions) -> None:
        from simlab.tasks.direct.franka_cabinet.franka_cabinet_env import DRAWER_OPENING_OBS

        finished = env.reset_buf  # the envs whose episode ended in this step (already reset)
        if not bool(finished.any()):
            return
        opening = env.extras["final_obs"]["policy"][:, DRAWER_OPENING_OBS]
        counts["success"] += int((finished & (opening >= min_opening_m)).sum())
        counts["episodes"] += int(finished.sum())

    return on_step, counts


def drawer_opens(min_opening_m: float = 0.2) -> Criterion:
    return episodes_succeed(
        f"the top drawer open >= {min_opening_m} m", partial(direct_cabinet_tracker, min_opening_m), episode_s=500 / 60
    )
