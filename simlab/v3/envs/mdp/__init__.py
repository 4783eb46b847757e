"""``isaaclab.envs.mdp`` of Isaac Lab 3.0: simlab's MDP terms, with quaternions in (x, y, z, w) where
3.0 code gives or reads them.

Everything is :mod:`simlab.envs.mdp`'s, except the terms that carry an orientation across the boundary:

* action terms' ``body_offset`` (``DifferentialInverseKinematicsActionCfg.OffsetCfg``,
  ``OperationalSpaceControllerActionCfg.OffsetCfg``): ``rot`` in (x, y, z, w), converted where the env
  is built, as asset configs are (:func:`simlab.v3._order.to_simlab`);
* ``UniformPoseCommandCfg``: its command (``get_command``, ``generated_commands``) is
  ``(x, y, z, qx, qy, qz, qw)``, as 3.0's reward terms read it;
* the observations ``root_quat_w``, ``body_pose_w`` and ``imu_orientation``: (x, y, z, w);
* ``body_incoming_wrench(sensor_cfg=...)`` reads a joint wrench sensor, as 3.0's does;
* the pose-tracking rewards 3.0 moved into ``isaaclab.envs.mdp`` (``position_command_error``,
  ``orientation_command_error`` and their ``_tanh`` forms, 2.x's reach terms): they read a simlab pose
  command's own (w, x, y, z) pose, and another command term's ``get_command`` as 3.0's (x, y, z, w).

simlab's own 2.x terms keep (w, x, y, z): they come from :mod:`simlab.envs.mdp`, never from here.
"""

from __future__ import annotations

from typing import Any

import torch

import simlab.envs.mdp as _mdp
from simlab.envs.mdp import *  # noqa: F403
from simlab.managers import SceneEntityCfg
from simlab.utils import configclass
from simlab.utils import math as _math2  # (w, x, y, z); private: a star import must not hand it to 3.0 code
from simlab.v3._order import xyzw_class

_ROBOT = SceneEntityCfg("robot")
_IMU = SceneEntityCfg("imu")


def _xyzw(quat: torch.Tensor) -> torch.Tensor:
    return quat[..., [1, 2, 3, 0]]


def root_quat_w(env: Any, make_quat_unique: bool = False, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Root orientation (x, y, z, w) (N, 4); with ``make_quat_unique`` the real part is kept >= 0."""
    return _xyzw(_mdp.root_quat_w(env, make_quat_unique, asset_cfg))


def body_pose_w(env: Any, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Poses of the bodies ``asset_cfg.body_ids`` relative to the env origin, ``(x, y, z, qx, qy, qz, qw)`` each."""
    pose = _mdp.body_pose_w(env, asset_cfg).view(env.num_envs, -1, 7)
    return torch.cat((pose[..., :3], _xyzw(pose[..., 3:])), dim=-1).reshape(env.num_envs, -1)


def body_incoming_wrench(
    env: Any, sensor_cfg: SceneEntityCfg | None = None, asset_cfg: SceneEntityCfg | None = None
) -> torch.Tensor:
    """``[force, torque]`` each body receives through its joint, its frame (N, 6 * bodies): Isaac Lab 3.0
    reads a joint wrench sensor (``sensor_cfg``); 2.x's ``asset_cfg`` (the articulation) is taken too."""
    if sensor_cfg is None:
        if asset_cfg is None:
            raise TypeError(
                "body_incoming_wrench needs sensor_cfg (a JointWrenchSensor) or asset_cfg (an articulation)."
            )
        return _mdp.body_incoming_wrench(env, asset_cfg)
    data = env.scene.sensors[sensor_cfg.name].data
    wrench = torch.cat((data.force[:, sensor_cfg.body_ids], data.torque[:, sensor_cfg.body_ids]), dim=-1)
    return wrench.reshape(env.num_envs, -1)


body_incoming_wrench.before_compile = _mdp.body_incoming_wrench.before_compile  # MuJoCo's post-constraint pass


def imu_orientation(env: Any, asset_cfg: SceneEntityCfg = _IMU) -> torch.Tensor:
    """The IMU's orientation in the world frame, (x, y, z, w)."""
    return _xyzw(_mdp.imu_orientation(env, asset_cfg))


class UniformPoseCommand(_mdp.UniformPoseCommand):
    """simlab's pose command; 3.0 code reads it as ``(x, y, z, qx, qy, qz, qw)`` (its metrics stay simlab's)."""

    @property
    def command(self) -> torch.Tensor:
        pose = self.pose_command_b
        return torch.cat((pose[:, :3], _xyzw(pose[:, 3:])), dim=-1)


@configclass
class UniformPoseCommandCfg(_mdp.UniformPoseCommandCfg):
    class_type: type = UniformPoseCommand


@configclass
class DifferentialInverseKinematicsActionCfg(_mdp.DifferentialInverseKinematicsActionCfg):
    OffsetCfg = xyzw_class(_mdp.DifferentialInverseKinematicsActionCfg.OffsetCfg, __name__)


@configclass
class OperationalSpaceControllerActionCfg(_mdp.OperationalSpaceControllerActionCfg):
    OffsetCfg = xyzw_class(_mdp.OperationalSpaceControllerActionCfg.OffsetCfg, __name__)


def _desired_pose_w(env: Any, command_name: str, asset_cfg: SceneEntityCfg) -> tuple[torch.Tensor, torch.Tensor]:
    """The commanded pose in the world frame, (w, x, y, z): the command is in the asset's root frame."""
    term = env.command_manager.get_term(command_name)
    if isinstance(term, _mdp.UniformPoseCommand):  # simlab's own term, 2.x's or 3.0's: its (w, x, y, z) pose
        pose_b = term.pose_command_b
    else:  # a command term of 3.0 code: (x, y, z, qx, qy, qz, qw)
        command = env.command_manager.get_command(command_name)
        pose_b = torch.cat((command[:, :3], command[:, 6:7], command[:, 3:6]), dim=-1)
    data = env.scene[asset_cfg.name].data
    return _math2.combine_frame_transforms(data.root_pos_w, data.root_quat_w, pose_b[:, :3], pose_b[:, 3:7])


def position_command_error(env: Any, asset_cfg: SceneEntityCfg, command_name: str = "ee_pose") -> torch.Tensor:
    """Distance [m] of the body ``asset_cfg.body_ids[0]`` from the commanded position."""
    des_pos_w, _ = _desired_pose_w(env, command_name, asset_cfg)
    return torch.linalg.norm(env.scene[asset_cfg.name].data.body_pos_w[:, asset_cfg.body_ids[0]] - des_pos_w, dim=1)


def position_command_error_tanh(
    env: Any, std: float = 0.1, *, asset_cfg: SceneEntityCfg, command_name: str = "ee_pose"
) -> torch.Tensor:
    return 1.0 - torch.tanh(position_command_error(env, asset_cfg=asset_cfg, command_name=command_name) / std)


def orientation_command_error(env: Any, asset_cfg: SceneEntityCfg, command_name: str = "ee_pose") -> torch.Tensor:
    """Shortest-path angle [rad] of the body ``asset_cfg.body_ids[0]`` from the commanded orientation."""
    _, des_quat_w = _desired_pose_w(env, command_name, asset_cfg)
    return _math2.quat_error_magnitude(env.scene[asset_cfg.name].data.body_quat_w[:, asset_cfg.body_ids[0]], des_quat_w)


def orientation_command_error_tanh(
    env: Any, std: float = 0.1, *, asset_cfg: SceneEntityCfg, command_name: str = "ee_pose"
) -> torch.Tensor:
    return 1.0 - torch.tanh(orientation_command_error(env, asset_cfg=asset_cfg, command_name=command_name) / std)


def __getattr__(name: str) -> Any:
    return getattr(_mdp, name)
