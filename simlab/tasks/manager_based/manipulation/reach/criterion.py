"""The Franka reach tasks' criterion: at the end of each command window, mean position error < 2 cm and
mean orientation error < 0.1 rad."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import torch

from simlab.tasks.utils.criteria import Criterion


def command_window_tracker() -> tuple[Callable[[Any, Any, Any], None], dict[str, list[torch.Tensor]]]:
    """An ``on_step`` hook keeping the reach task's position [m] and orientation [rad] errors of the
    hand to its ``ee_pose`` command on the last step of every command window."""
    errors: dict[str, list[torch.Tensor]] = {"position": [], "orientation": []}

    def on_step(env, obs, actions) -> None:
        from simlab.managers import SceneEntityCfg
        from simlab.tasks.manager_based.manipulation.reach import mdp

        term = env.command_manager.get_term("ee_pose")
        ending = term.time_left <= env.step_dt * 0.5  # the command changes at the next step
        if not bool(ending.any()):
            return
        hand = SceneEntityCfg("robot", body_names=[term.cfg.body_name])
        hand.resolve(env.scene)
        errors["position"].append(mdp.position_command_error(env, "ee_pose", hand)[ending].cpu())
        errors["orientation"].append(mdp.orientation_command_error(env, "ee_pose", hand)[ending].cpu())

    return on_step, errors


def reaches_pose(position_m: float = 0.02, orientation_rad: float = 0.1, window_s: float = 4.0) -> Criterion:
    """Score: the larger of the mean errors as a fraction of their tolerance (passes at < 1)."""

    def judge(result: dict[str, float], errors: dict[str, list[torch.Tensor]]) -> tuple[float, bool]:
        if not errors["position"]:
            return math.inf, False
        position = float(torch.cat(errors["position"]).mean())
        orientation = float(torch.cat(errors["orientation"]).mean())
        score = max(position / position_m, orientation / orientation_rad)
        return score, score < 1.0

    return Criterion(
        f"at the end of each command window, mean position error < {position_m} m and mean orientation error"
        f" < {orientation_rad} rad (score: the larger error over its tolerance, < 1)",
        command_window_tracker,
        judge,
        min_seconds=window_s + 0.5,
    )
