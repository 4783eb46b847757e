"""The reach tasks' criterion: at the end of each command window, mean position error < 2 cm and
mean orientation error < 0.1 rad. The errors are the hand's to the ``ee_pose`` command in the robot's
root frame, or, for a task that tracks the command in another frame (the deployed UR10e's, in the
"base" frame of Universal Robots' controller), those a frame transformer reads: its first target in
its source frame. A task with a command per hand (the two-arm OpenArm's ``left_ee_pose`` and
``right_ee_pose``) is judged on each hand's: every hand's mean errors must be within tolerance."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import torch

from simlab.tasks.utils.criteria import Criterion

Errors = dict[str, dict[str, list[torch.Tensor]]]
"""Per command name, the position [m] and orientation [rad] errors at the windows' ends."""


def command_window_tracker(
    frame: str | None = None, commands: tuple[str, ...] = ("ee_pose",)
) -> tuple[Callable[[Any, Any, Any], None], Errors]:
    """An ``on_step`` hook keeping, for each pose command of ``commands``, the position [m] and
    orientation [rad] errors of its body (the command's ``body_name``) to it on the last step of every
    command window; with ``frame``, the errors of that frame transformer's first target, read in its
    source frame, to the (one) command."""
    errors: Errors = {name: {"position": [], "orientation": []} for name in commands}

    def on_step(env, obs, actions) -> None:
        from simlab.managers import SceneEntityCfg
        from simlab.tasks.manager_based.manipulation.reach import mdp
        from simlab.utils.math import quat_error_magnitude

        for name in commands:
            term = env.command_manager.get_term(name)
            ending = term.time_left <= env.step_dt * 0.5  # the command changes at the next step
            if not bool(ending.any()):
                continue
            if frame is None:
                hand = SceneEntityCfg("robot", body_names=[term.cfg.body_name])
                hand.resolve(env.scene)
                position = mdp.position_command_error(env, name, hand)
                orientation = mdp.orientation_command_error(env, name, hand)
            else:
                data, command = env.scene[frame].data, term.command
                position = torch.linalg.norm(data.target_pos_source[:, 0] - command[:, :3], dim=1)
                orientation = quat_error_magnitude(data.target_quat_source[:, 0], command[:, 3:7])
            errors[name]["position"].append(position[ending].cpu())
            errors[name]["orientation"].append(orientation[ending].cpu())

    return on_step, errors


def reaches_pose(
    position_m: float = 0.02,
    orientation_rad: float = 0.1,
    window_s: float = 4.0,
    frame: str | None = None,
    commands: tuple[str, ...] = ("ee_pose",),
) -> Criterion:
    """Score: the largest of the mean errors (each command's position and orientation) as a fraction of
    its tolerance (passes at < 1). ``frame``: the frame transformer whose first target tracks the
    command; ``commands``: the pose commands judged, one per hand (see :func:`command_window_tracker`)."""

    def judge(result: dict[str, float], errors: Errors) -> tuple[float, bool]:
        fractions = []
        for kinds in errors.values():
            if not kinds["position"]:
                return math.inf, False
            fractions.append(float(torch.cat(kinds["position"]).mean()) / position_m)
            fractions.append(float(torch.cat(kinds["orientation"]).mean()) / orientation_rad)
        score = max(fractions)
        return score, score < 1.0

    hands = "" if len(commands) == 1 else f" (each of {', '.join(commands)})"
    return Criterion(
        f"at the end of each command window, mean position error < {position_m} m and mean orientation error"
        f" < {orientation_rad} rad{hands} (score: the larger error over its tolerance, < 1)",
        lambda: command_window_tracker(frame, commands),
        judge,
        min_seconds=window_s + 0.5,
    )


def reaches_pose_in_base_frame() -> Criterion:
    """The deployed UR10e's: ``wrist_3_link`` in Universal Robots' "base" frame (``ee_frame_wrt_base_frame``)."""
    return reaches_pose(frame="ee_frame_wrt_base_frame")


def reaches_pose_with_both_hands() -> Criterion:
    """The two-arm OpenArm's: each hand to its own command (``left_ee_pose``, ``right_ee_pose``)."""
    return reaches_pose(commands=("left_ee_pose", "right_ee_pose"))
