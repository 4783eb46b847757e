"""Terminations of the stack task (Isaac Lab's ``stack/mdp/terminations.py``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import SceneEntityCfg

from .observations import _CUBES, _ROBOT, _gripper_open, object_pose_w

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

__all__ = ["cubes_stacked"]


def cubes_stacked(
    env: ManagerBasedRLEnv,
    robot_cfg: SceneEntityCfg = _ROBOT,
    cube_1_cfg: SceneEntityCfg = _CUBES[0],
    cube_2_cfg: SceneEntityCfg = _CUBES[1],
    cube_3_cfg: SceneEntityCfg | None = _CUBES[2],
    xy_threshold: float = 0.04,
    height_threshold: float = 0.005,
    height_diff: float = 0.0468,
    atol: float = 0.0001,
    rtol: float = 0.0001,
) -> torch.Tensor:
    """(N,) bool: cube 2 sits on cube 1 and cube 3 on cube 2 (each within ``xy_threshold`` [m]
    horizontally and ``height_diff`` [m] higher, to ``height_threshold``), and the gripper is open.
    ``cube_3_cfg=None`` judges a stack of two (Isaac Lab's two-cube variants). A cube that is a rigid
    object collection is judged by its object in focus."""
    robot = env.scene[robot_cfg.name]
    cubes = [c for c in (cube_1_cfg, cube_2_cfg, cube_3_cfg) if c is not None]
    stacked = _gripper_open(env, robot, atol, rtol)
    for lower, upper in zip(cubes, cubes[1:]):
        diff = object_pose_w(env, lower)[0] - object_pose_w(env, upper)[0]
        stacked = stacked & (torch.linalg.vector_norm(diff[:, :2], dim=1) < xy_threshold)
        stacked = stacked & (diff[:, 2].abs() - height_diff < height_threshold) & (diff[:, 2] < 0.0)
    return stacked
