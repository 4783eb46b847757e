"""The velocity tasks' criteria: the base's planar velocity follows the command (mean error <= 0.25 m/s);
for the humanoids the yaw rate too, with few falls; on rough ground, the terrain curriculum's level."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import torch

import simlab.utils.math as math_utils
from simlab.tasks.utils.criteria import Criterion


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


# The humanoids' bar (issue 39): planar velocity and yaw rate tracked over a 20 s episode with the
# commands resampled, and few falls.
BIPED_MAX_SPEED_ERROR = 0.25  # m/s
BIPED_MAX_YAW_RATE_ERROR = 0.3  # rad/s
BIPED_MAX_FALL_RATE = 0.05  # falls per env per 20 s


def biped_tracker() -> tuple[Callable[[Any, Any, Any], None], dict[str, float]]:
    """An ``on_step`` hook summing the planar velocity error (in the yaw frame, where the command
    lives), the yaw-rate error (world z) and the falls (terminations that are not time-outs)."""
    sums = {"speed": 0.0, "yaw_rate": 0.0, "falls": 0, "samples": 0, "steps": 0, "seconds": 0.0}

    def on_step(env, obs, actions) -> None:
        base = env.unwrapped
        command = base.command_manager.get_command("base_velocity")
        data = base.scene["robot"].data
        velocity = math_utils.quat_apply_inverse(math_utils.yaw_quat(data.root_quat_w), data.root_lin_vel_w)
        sums["speed"] += float(torch.linalg.norm(command[:, :2] - velocity[:, :2], dim=-1).sum())
        sums["yaw_rate"] += float((command[:, 2] - data.root_ang_vel_w[:, 2]).abs().sum())
        sums["falls"] += int(base.termination_manager.terminated.sum())
        sums["samples"] += command.shape[0]
        sums["steps"] += 1
        sums["seconds"] += base.step_dt

    return on_step, sums


def biped_tracks_velocity() -> Criterion:
    def judge(result: dict[str, float], sums: dict[str, float]) -> tuple[float, bool]:
        samples = max(1, sums["samples"])
        speed, yaw_rate = sums["speed"] / samples, sums["yaw_rate"] / samples
        envs = samples / max(1, sums["steps"])
        fall_rate = sums["falls"] / envs * 20.0 / max(sums["seconds"], 1e-9)
        passed = speed < BIPED_MAX_SPEED_ERROR and yaw_rate < BIPED_MAX_YAW_RATE_ERROR
        return speed, passed and fall_rate < BIPED_MAX_FALL_RATE

    return Criterion(
        f"mean |v_xy command - v_xy| < {BIPED_MAX_SPEED_ERROR} m/s, |yaw-rate error| < {BIPED_MAX_YAW_RATE_ERROR}"
        f" rad/s, < {BIPED_MAX_FALL_RATE:.0%} falls per env in 20 s",
        biped_tracker,
        judge,
        min_seconds=20.0,
    )


def terrain_level_tracker() -> tuple[Callable[[Any, Any, Any], None], dict[str, float]]:
    """An ``on_step`` hook keeping the envs' mean terrain level (the curriculum's row) after each step."""
    level = {"mean": 0.0}

    def on_step(env, obs, actions) -> None:
        level["mean"] = float(env.unwrapped.scene.terrain.terrain_levels.float().mean())

    return on_step, level


def reaches_terrain_level(min_level: float = 3.0, seconds: float = 60.0) -> Criterion:
    """Rough terrain: after ``seconds`` of play under the terrain curriculum (each episode end moves an
    env a row up or down), the envs' mean row is at least ``min_level``."""

    def judge(result: dict[str, float], level: dict[str, float]) -> tuple[float, bool]:
        return level["mean"], level["mean"] >= min_level

    return Criterion(
        f"mean terrain level >= {min_level:g} after {seconds:g} s of the curriculum",
        terrain_level_tracker,
        judge,
        min_seconds=seconds,
    )
