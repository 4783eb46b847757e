"""Reward terms of the in-hand task (the orientation goal comes from the command term)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import SceneEntityCfg
from simlab.utils import math as math_utils

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

__all__ = ["success_bonus", "track_orientation_inv_l2", "track_pos_l2"]

_OBJECT = SceneEntityCfg("object")


def _orientation_error(env: ManagerBasedRLEnv, command_name: str, object_cfg: SceneEntityCfg) -> torch.Tensor:
    """The object's angle to its goal, computed once per state and goal: the bonus and the tracking term
    read it in the same step (Python's cache, so a step captured as a graph records one computation)."""
    command = env.command_manager.get_term(command_name)
    key = (env.sim.physics.state_version, command.goal_version, object_cfg.name, torch.is_inference_mode_enabled())
    cache = command.__dict__.setdefault("_orientation_error_cache", {})
    if command_name not in cache or cache[command_name][0] != key:
        error = math_utils.quat_error_magnitude(env.scene[object_cfg.name].data.root_quat_w, command.command[:, 3:7])
        cache[command_name] = (key, error)
    return cache[command_name][1]


def success_bonus(env: ManagerBasedRLEnv, command_name: str, object_cfg: SceneEntityCfg = _OBJECT) -> torch.Tensor:
    """1 where the object's orientation is within the command's success threshold of the goal, else 0."""
    threshold = env.command_manager.get_term(command_name).cfg.orientation_success_threshold
    return (_orientation_error(env, command_name, object_cfg) <= threshold).float()


def track_pos_l2(env: ManagerBasedRLEnv, command_name: str, object_cfg: SceneEntityCfg = _OBJECT) -> torch.Tensor:
    """Distance [m] of the object from the goal position (env frame)."""
    goal_pos_e = env.command_manager.get_term(command_name).command[:, 0:3]
    object_pos_e = env.scene[object_cfg.name].data.root_pos_w - env.scene.env_origins
    return torch.norm(goal_pos_e - object_pos_e, p=2, dim=-1)


def track_orientation_inv_l2(
    env: ManagerBasedRLEnv,
    command_name: str,
    object_cfg: SceneEntityCfg = _OBJECT,
    rot_eps: float = 1e-3,
) -> torch.Tensor:
    """``1 / (orientation error + rot_eps)``: grows steeply as the object nears the goal orientation."""
    return 1.0 / (_orientation_error(env, command_name, object_cfg) + rot_eps)
