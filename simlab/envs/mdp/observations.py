"""Observation terms: ``func(env, ...) -> (num_envs, dim)``. Isaac Lab's names and meanings.

Frames: ``_w`` is the world frame (positions without the env origin where noted), ``base_*`` /
``_b`` the robot's root frame.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils
from simlab.envs.utils.io_descriptors import (
    generic_io_descriptor,
    record_joint_names,
    record_joint_pos_offsets,
    record_joint_vel_offsets,
)
from simlab.managers import SceneEntityCfg

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv, ManagerBasedRLEnv

_ROBOT = SceneEntityCfg("robot")


# -- root state ------------------------------------------------------------------------------------


def base_pos_z(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Root height in the world frame (N, 1)."""
    return env.scene[asset_cfg.name].data.root_pos_w[:, 2:3]


def base_lin_vel(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Root linear velocity in the root frame (N, 3)."""
    return env.scene[asset_cfg.name].data.root_lin_vel_b


def base_ang_vel(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Root angular velocity in the root frame (N, 3)."""
    return env.scene[asset_cfg.name].data.root_ang_vel_b


def projected_gravity(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Gravity direction (unit vector) in the root frame (N, 3)."""
    return env.scene[asset_cfg.name].data.projected_gravity_b


def root_pos_w(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Root position relative to the env origin, world axes (N, 3)."""
    return env.scene[asset_cfg.name].data.root_pos_w - env.scene.env_origins


def root_quat_w(
    env: ManagerBasedEnv, make_quat_unique: bool = False, asset_cfg: SceneEntityCfg = _ROBOT
) -> torch.Tensor:
    """Root orientation (w, x, y, z) (N, 4); with ``make_quat_unique`` the real part is kept >= 0."""
    quat = env.scene[asset_cfg.name].data.root_quat_w
    return math_utils.quat_unique(quat) if make_quat_unique else quat


def root_lin_vel_w(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    return env.scene[asset_cfg.name].data.root_lin_vel_w


def root_ang_vel_w(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    return env.scene[asset_cfg.name].data.root_ang_vel_w


# -- body state ------------------------------------------------------------------------------------


def body_pose_w(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Poses of the bodies ``asset_cfg.body_ids``, positions relative to the env origin: (N, 7 * bodies),
    ``(x, y, z, qw, qx, qy, qz)`` per body."""
    pose = env.scene[asset_cfg.name].data.body_pose_w[:, asset_cfg.body_ids, :7].clone()
    pose[..., :3] -= env.scene.env_origins.unsqueeze(1)
    return pose.reshape(env.num_envs, -1)


def body_projected_gravity_b(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Gravity direction (unit vector) in the frame of each body ``asset_cfg.body_ids``: (N, 3 * bodies)."""
    data = env.scene[asset_cfg.name].data
    body_quat = data.body_quat_w[:, asset_cfg.body_ids]
    gravity = data.GRAVITY_VEC_W.unsqueeze(1).expand(-1, body_quat.shape[1], -1)
    return math_utils.quat_apply_inverse(body_quat, gravity).reshape(env.num_envs, -1)


# -- joint state -----------------------------------------------------------------------------------


def joint_pos(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    return env.scene[asset_cfg.name].data.joint_pos[:, asset_cfg.joint_ids]


@generic_io_descriptor(observation_type="JointState", on_inspect=[record_joint_names, record_joint_pos_offsets])
def joint_pos_rel(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Joint positions minus the default joint positions."""
    data = env.scene[asset_cfg.name].data
    return data.joint_pos[:, asset_cfg.joint_ids] - data.default_joint_pos[:, asset_cfg.joint_ids]


def joint_pos_limit_normalized(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Joint positions scaled to [-1, 1] between the soft joint limits."""
    data = env.scene[asset_cfg.name].data
    limits = data.soft_joint_pos_limits[:, asset_cfg.joint_ids]
    return math_utils.scale_transform(data.joint_pos[:, asset_cfg.joint_ids], limits[..., 0], limits[..., 1])


def joint_vel(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    return env.scene[asset_cfg.name].data.joint_vel[:, asset_cfg.joint_ids]


@generic_io_descriptor(observation_type="JointState", on_inspect=[record_joint_names, record_joint_vel_offsets])
def joint_vel_rel(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Joint velocities minus the default joint velocities."""
    data = env.scene[asset_cfg.name].data
    return data.joint_vel[:, asset_cfg.joint_ids] - data.default_joint_vel[:, asset_cfg.joint_ids]


def joint_effort(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _ROBOT) -> torch.Tensor:
    """Efforts the actuators applied to the joints in the last physics step."""
    return env.scene[asset_cfg.name].data.applied_torque[:, asset_cfg.joint_ids]


# -- actions and commands --------------------------------------------------------------------------


def last_action(env: ManagerBasedEnv, action_name: str | None = None) -> torch.Tensor:
    """The last action (all terms), or the raw action of the term ``action_name``."""
    if action_name is None:
        return env.action_manager.action
    return env.action_manager.get_term(action_name).raw_actions


def generated_commands(env: ManagerBasedRLEnv, command_name: str) -> torch.Tensor:
    return env.command_manager.get_command(command_name)


# -- time ------------------------------------------------------------------------------------------


def current_time_s(env: ManagerBasedRLEnv) -> torch.Tensor:
    """Time since the episode began, in seconds (N, 1)."""
    return env.episode_length_buf.unsqueeze(1) * env.step_dt


def remaining_time_s(env: ManagerBasedRLEnv) -> torch.Tensor:
    """Time left until the episode's time limit, in seconds (N, 1)."""
    return env.max_episode_length_s - current_time_s(env)


# -- sensors ---------------------------------------------------------------------------------------


def height_scan(env: ManagerBasedEnv, sensor_cfg: SceneEntityCfg, offset: float = 0.5) -> torch.Tensor:
    """Height of the scanner above each ray's hit, minus ``offset`` (N, rays): about 0 on flat
    ground when the scanner is ``offset`` metres up."""
    sensor = env.scene.sensors[sensor_cfg.name]
    return sensor.data.pos_w[:, 2].unsqueeze(1) - sensor.data.ray_hits_w[..., 2] - offset


def body_incoming_wrench(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg) -> torch.Tensor:
    """The wrench each body receives from its parent through its joint, ``[force, torque]`` in the
    body's frame (N, 6 * bodies): Isaac Lab's ``body_incoming_joint_wrench_b`` (MuJoCo's ``cfrc_int``,
    see ``ArticulationData.body_incoming_joint_wrench_b``)."""
    wrench = env.scene[asset_cfg.name].data.body_incoming_joint_wrench_b[:, asset_cfg.body_ids]
    return wrench.reshape(env.num_envs, -1)


def _compute_body_interaction_forces(env: ManagerBasedEnv) -> None:
    from simlab.sim.simulation_context import compute_body_interaction_forces

    compute_body_interaction_forces(env.sim.spec)


body_incoming_wrench.before_compile = _compute_body_interaction_forces
"""The env runs this before the model compiles: the term needs MuJoCo's post-constraint pass."""

_IMU = SceneEntityCfg("imu")


def imu_orientation(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _IMU) -> torch.Tensor:
    """An IMU's orientation (w, x, y, z) in the world frame (N, 4)."""
    return env.scene[asset_cfg.name].data.quat_w


def imu_projected_gravity(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _IMU) -> torch.Tensor:
    """Gravity direction (unit vector) in an IMU's frame (N, 3)."""
    return env.scene[asset_cfg.name].data.projected_gravity_b


def imu_ang_vel(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _IMU) -> torch.Tensor:
    """An IMU's angular velocity in its own frame, rad/s (N, 3)."""
    return env.scene[asset_cfg.name].data.ang_vel_b


def imu_lin_acc(env: ManagerBasedEnv, asset_cfg: SceneEntityCfg = _IMU) -> torch.Tensor:
    """An IMU's linear acceleration in its own frame, m/s^2 (N, 3)."""
    return env.scene[asset_cfg.name].data.lin_acc_b


_TILED_CAMERA = SceneEntityCfg("tiled_camera")


def image(
    env: ManagerBasedEnv,
    sensor_cfg: SceneEntityCfg = _TILED_CAMERA,
    data_type: str = "rgb",
    convert_perspective_to_orthogonal: bool = False,
    normalize: bool = True,
) -> torch.Tensor:
    """A camera's images (N, H, W, C) as float32. ``normalize``: RGB to [0, 1] minus each image's mean
    colour; depths with 0 where nothing is hit (inf). ``convert_perspective_to_orthogonal`` turns
    ``distance_to_camera`` into distance to the image plane."""
    camera = env.scene.sensors[sensor_cfg.name]
    images = camera.data.output[data_type]
    if data_type == "distance_to_camera" and convert_perspective_to_orthogonal:
        images = math_utils.orthogonalize_perspective_depth(images, camera.data.intrinsic_matrices)
    images = images.float()
    if normalize and data_type in ("rgb", "rgba"):
        images = images / 255.0
        images = images - images.mean(dim=(1, 2), keepdim=True)
    elif normalize and data_type in ("depth", "distance_to_image_plane", "distance_to_camera"):
        images = torch.where(torch.isinf(images), 0.0, images)
    return images.clone()
