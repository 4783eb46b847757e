"""The reach tasks' criterion: at the end of each command window, mean position error < 2 cm and
mean orientation error < 0.1 rad. The errors are the hand's to the ``ee_pose`` command in the robot's
root frame, or, for a task that tracks the command in another frame (the deployed UR10e's, in the
"base" frame of Universal Robots' controller), those a frame transformer reads: its first target in
its source frame."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import torch

from simlab.tasks.utils.criteria import Criterion


def command_window_tracker(
    frame: str | None = None,
) -> tuple[Callable[[Any, Any, Any], None], dict[str, list[torch.Tensor]]]:
    """An ``on_step`` hook keeping the reach task's position [m] and orientation [rad] errors of the
    hand to its ``ee_pose`` command on the last step of every command window; with ``frame``, the
    errors of that frame transformer's first target, read in its source frame, to the command."""
    errors: dict[str, list[torch.Tensor]] = {"position": [], "orientation": []}

    def on_step(env, obs, actions) -> None:
        from simlab.managers import SceneEntityCfg
        from simlab.tasks.manager_based.manipulation.reach import mdp
        from simlab.utils.math import quat_error_magnitude

        term = env.command_manager.get_term("ee_pose")
        ending = term.time_left <= env.step_dt * 0.5  # the command changes at the next step
        if not bool(ending.any()):
            return
        if frame is None:
            hand = SceneEntityCfg("robot", body_names=[term.cfg.body_name])
            hand.resolve(env.scene)
            position = mdp.position_command_error(env, "ee_pose", hand)
            orientation = mdp.orientation_command_error(env, "ee_pose", hand)
        else:
            data, command = env.scene[frame].data, term.command
            position = torch.linalg.norm(data.target_pos_source[:, 0] - command[:, :3], dim=1)
            orientation = quat_error_magnitude(data.target_quat_source[:, 0], command[:, 3:7])
        errors["position"].append(position[ending].cpu())
        errors["orientation"].append(orientation[ending].cpu())

    return on_step, errors


def reaches_pose(
    position_m: float = 0.02, orientation_rad: float = 0.1, window_s: float = 4.0, frame: str | None = None
) -> Criterion:
    """Score: the larger of the mean errors as a fraction of their tolerance (passes at < 1). ``frame``:
    the frame transformer whose first target tracks the command (see :func:`command_window_tracker`)."""

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
        lambda: command_window_tracker(frame),
        judge,
        min_seconds=window_s + 0.5,
    )


def reaches_pose_in_base_frame() -> Criterion:
    """The deployed UR10e's: ``wrist_3_link`` in Universal Robots' "base" frame (``ee_frame_wrt_base_frame``)."""
    return reaches_pose(frame="ee_frame_wrt_base_frame")
