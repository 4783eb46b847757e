"""Observations of the stack task (Isaac Lab's ``stack/mdp/observations.py``): the cubes' poses, the
end effector's pose and the gripper's opening, and the subtask signals ``object_grasped`` and
``object_stacked``.

The gripper terms read three fields of the env config: ``gripper_joint_names`` (the two finger joints;
when unset, the joints of the ``gripper_action``), ``gripper_open_val`` (their open position) and
``gripper_threshold`` (how far from open a finger must be to count as closed on something).
Isaac Lab's suction-cup branches are left out: simlab has no surface gripper.

A cube may also be a rigid object collection of candidate objects, one of which the event
``randomize_rigid_objects_in_focus`` brings into each env (Isaac Lab's instance-randomized stack
task): every term here then reads the object in focus (``object_pose_w``), so Isaac Lab's
``instance_randomize_*`` terms are the same functions. Before that event has run, a collection's
first object is in focus (Isaac Lab's terms return -1s then, nine wide whatever the term).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.assets import RigidObjectCollection
from simlab.managers import SceneEntityCfg
from simlab.utils.errors import ConfigError

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

__all__ = [
    "cube_orientations_in_world_frame",
    "cube_positions_in_world_frame",
    "ee_frame_pos",
    "ee_frame_quat",
    "gripper_pos",
    "instance_randomize_cube_orientations_in_world_frame",
    "instance_randomize_cube_positions_in_world_frame",
    "instance_randomize_object_obs",
    "object_grasped",
    "object_obs",
    "object_pose_w",
    "object_stacked",
]

_ROBOT, _EE_FRAME = SceneEntityCfg("robot"), SceneEntityCfg("ee_frame")
_CUBES = (SceneEntityCfg("cube_1"), SceneEntityCfg("cube_2"), SceneEntityCfg("cube_3"))


def object_pose_w(env: ManagerBasedRLEnv, asset_cfg: SceneEntityCfg) -> tuple[torch.Tensor, torch.Tensor]:
    """(N, 3) position and (N, 4) orientation (w, x, y, z) in the world frame of a rigid object, or of
    the object in focus of a rigid object collection (``env.rigid_objects_in_focus``, the column the
    focus event gave the collection; its first object before that event has run)."""
    asset = env.scene[asset_cfg.name]
    if not isinstance(asset, RigidObjectCollection):
        return asset.data.root_pos_w, asset.data.root_quat_w
    columns = getattr(env, "rigid_object_focus_columns", {})
    if asset_cfg.name not in columns:
        return asset.data.object_pos_w[:, 0], asset.data.object_quat_w[:, 0]
    chosen = env.rigid_objects_in_focus[:, columns[asset_cfg.name]]
    rows = torch.arange(env.num_envs, device=chosen.device)
    return asset.data.object_pos_w[rows, chosen], asset.data.object_quat_w[rows, chosen]


def cube_positions_in_world_frame(
    env: ManagerBasedRLEnv,
    cube_1_cfg: SceneEntityCfg = _CUBES[0],
    cube_2_cfg: SceneEntityCfg = _CUBES[1],
    cube_3_cfg: SceneEntityCfg = _CUBES[2],
) -> torch.Tensor:
    """(N, 9) the three cubes' positions in the world frame (env origins included, as Isaac Lab's)."""
    return torch.cat([object_pose_w(env, c)[0] for c in (cube_1_cfg, cube_2_cfg, cube_3_cfg)], dim=1)


def cube_orientations_in_world_frame(
    env: ManagerBasedRLEnv,
    cube_1_cfg: SceneEntityCfg = _CUBES[0],
    cube_2_cfg: SceneEntityCfg = _CUBES[1],
    cube_3_cfg: SceneEntityCfg = _CUBES[2],
) -> torch.Tensor:
    """(N, 12) the three cubes' orientations (w, x, y, z) in the world frame."""
    return torch.cat([object_pose_w(env, c)[1] for c in (cube_1_cfg, cube_2_cfg, cube_3_cfg)], dim=1)


def object_obs(
    env: ManagerBasedRLEnv,
    cube_1_cfg: SceneEntityCfg = _CUBES[0],
    cube_2_cfg: SceneEntityCfg = _CUBES[1],
    cube_3_cfg: SceneEntityCfg = _CUBES[2],
    ee_frame_cfg: SceneEntityCfg = _EE_FRAME,
) -> torch.Tensor:
    """(N, 39) Isaac Lab's layout: each cube's position (env frame) and orientation, the vectors from
    the end effector to each cube, and cube 2 to 1, 3 to 2 and 3 to 1."""
    pos, quat = zip(*(object_pose_w(env, c) for c in (cube_1_cfg, cube_2_cfg, cube_3_cfg)))
    ee_pos = env.scene[ee_frame_cfg.name].data.target_pos_w[:, 0, :]
    origins = env.scene.env_origins
    return torch.cat(
        (
            pos[0] - origins,
            quat[0],
            pos[1] - origins,
            quat[1],
            pos[2] - origins,
            quat[2],
            pos[0] - ee_pos,
            pos[1] - ee_pos,
            pos[2] - ee_pos,
            pos[0] - pos[1],
            pos[1] - pos[2],
            pos[0] - pos[2],
        ),
        dim=1,
    )


# Isaac Lab's names for the terms of its instance-randomized stack task: the same terms (see above)
instance_randomize_cube_positions_in_world_frame = cube_positions_in_world_frame
instance_randomize_cube_orientations_in_world_frame = cube_orientations_in_world_frame
instance_randomize_object_obs = object_obs


def ee_frame_pos(env: ManagerBasedRLEnv, ee_frame_cfg: SceneEntityCfg = _EE_FRAME) -> torch.Tensor:
    """(N, 3) the end effector's position in the env frame."""
    return env.scene[ee_frame_cfg.name].data.target_pos_w[:, 0, :] - env.scene.env_origins


def ee_frame_quat(env: ManagerBasedRLEnv, ee_frame_cfg: SceneEntityCfg = _EE_FRAME) -> torch.Tensor:
    """(N, 4) the end effector's orientation in the world frame."""
    return env.scene[ee_frame_cfg.name].data.target_quat_w[:, 0, :]


def _finger_ids(env: ManagerBasedRLEnv, robot) -> list[int]:
    """The two finger joints: ``env.cfg.gripper_joint_names``, else those of the gripper action (Isaac
    Lab's Franka stack config of 2.x sets no names; its gripper action names the fingers)."""
    names = getattr(env.cfg, "gripper_joint_names", None)
    if names is None:
        gripper_action = getattr(env.cfg.actions, "gripper_action", None)
        names = getattr(gripper_action, "joint_names", None)
    if names is None:
        raise ConfigError(
            "The stack task's gripper terms need env.cfg.gripper_joint_names (the two finger joints, e.g."
            " ['panda_finger_.*']) or a gripper_action naming them."
        )
    ids, found = robot.find_joints(names)
    if len(ids) != 2:
        raise ConfigError(f"gripper joints {names} must name a parallel gripper's two joints, found {found}.")
    return ids


def gripper_pos(env: ManagerBasedRLEnv, robot_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """(N, 2) the finger joints' positions, the second negated (Isaac Lab's convention)."""
    robot = env.scene[robot_cfg.name]
    first, second = _finger_ids(env, robot)
    return torch.stack((robot.data.joint_pos[:, first], -robot.data.joint_pos[:, second]), dim=1)


def object_grasped(
    env: ManagerBasedRLEnv,
    robot_cfg: SceneEntityCfg,
    ee_frame_cfg: SceneEntityCfg,
    object_cfg: SceneEntityCfg,
    diff_threshold: float = 0.06,
) -> torch.Tensor:
    """(N,) bool: the object is within ``diff_threshold`` [m] of the end effector and both fingers are
    more than ``env.cfg.gripper_threshold`` from open (closed on something)."""
    robot = env.scene[robot_cfg.name]
    object_pos = object_pose_w(env, object_cfg)[0]
    ee_pos = env.scene[ee_frame_cfg.name].data.target_pos_w[:, 0, :]
    near = torch.linalg.vector_norm(object_pos - ee_pos, dim=1) < diff_threshold
    fingers = _fingers(env, robot)
    closed = ((fingers - env.cfg.gripper_open_val).abs() > env.cfg.gripper_threshold).all(dim=1)
    return near & closed


def object_stacked(
    env: ManagerBasedRLEnv,
    robot_cfg: SceneEntityCfg,
    upper_object_cfg: SceneEntityCfg,
    lower_object_cfg: SceneEntityCfg,
    xy_threshold: float = 0.05,
    height_threshold: float = 0.005,
    height_diff: float = 0.0468,
) -> torch.Tensor:
    """(N,) bool: the upper object rests on the lower one (centres within ``xy_threshold`` [m]
    horizontally, at most ``height_diff + height_threshold`` apart vertically) and the gripper is open
    (released it)."""
    robot = env.scene[robot_cfg.name]
    diff = object_pose_w(env, upper_object_cfg)[0] - object_pose_w(env, lower_object_cfg)[0]
    stacked = (torch.linalg.vector_norm(diff[:, :2], dim=1) < xy_threshold) & (
        diff[:, 2].abs() - height_diff < height_threshold
    )
    return stacked & _gripper_open(env, robot)


def _fingers(env: ManagerBasedRLEnv, robot) -> torch.Tensor:
    """(N, 2) the finger joints' positions (indexed by ints: no index tensor copied to the device,
    which a step being captured as a CUDA graph may not do)."""
    first, second = _finger_ids(env, robot)
    return torch.stack((robot.data.joint_pos[:, first], robot.data.joint_pos[:, second]), dim=1)


def _gripper_open(env: ManagerBasedRLEnv, robot, atol: float = 1e-4, rtol: float = 1e-4) -> torch.Tensor:
    fingers = _fingers(env, robot)
    open_val = torch.full_like(fingers, env.cfg.gripper_open_val)
    return torch.isclose(fingers, open_val, atol=atol, rtol=rtol).all(dim=1)
