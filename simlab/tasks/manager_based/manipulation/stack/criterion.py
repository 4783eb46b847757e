"""The stack tasks' criterion: >= 70 % of the episodes end with the three cubes stacked (the task's
``success`` termination).

The bar is set for a policy trained from demonstrations, as Isaac Lab trains this task (behaviour
cloning on recorded or Mimic-generated demonstrations), not with RL: such policies stack most but
not all of the time. The scripted state machine (scripts/environments/state_machine/stack_cube_sm.py)
stacked 49 of 49 episodes on the CPU, and simlab's behaviour cloning from 1000 of its demonstrations
(scripts/imitation_learning/bc.py) 96 of 102 (0.94; docs/manipulation.md); on the instance-randomized
IK-Rel task, through clipped delta poses, the machine stacked 45 of 45 and the cloned policy 123 of 127.
Episodes that end any other way (a cube dropped, the 30 s limit) count as failed.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from simlab.tasks.utils.criteria import Criterion

EPISODE_S = 30.0
"""The stack task's episode length [s]: a verdict needs at least one whole episode."""


def stack_tracker() -> tuple[Callable[[Any, Any, Any], None], dict[str, int]]:
    """An ``on_step`` hook counting finished episodes and those the ``success`` termination ended."""
    counts = {"success": 0, "episodes": 0}

    def on_step(env, obs, actions) -> None:
        manager = env.termination_manager
        done = manager.terminated | manager.time_outs
        if bool(done.any()):
            counts["success"] += int((manager.get_term("success") & done).sum())
            counts["episodes"] += int(done.sum())

    return on_step, counts


def stacks_cubes(rate: float = 0.7) -> Criterion:
    """Score: the share of finished episodes that ended stacked (passes at >= ``rate``)."""

    def judge(result: dict[str, float], counts: dict[str, int]) -> tuple[float, bool]:
        if not counts["episodes"]:
            return 0.0, False
        share = counts["success"] / counts["episodes"]
        return share, share >= rate

    return Criterion(
        f">= {rate:.0%} of the episodes end with the three cubes stacked (a bar for a demonstration-trained"
        " policy; Isaac Lab trains this task by imitation learning, not RL)",
        stack_tracker,
        judge,
        min_seconds=EPISODE_S + 0.5,
    )
