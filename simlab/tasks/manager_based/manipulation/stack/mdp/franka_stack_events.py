"""Reset events of the stack task (Isaac Lab's ``stack/mdp/franka_stack_events.py``): the arm's start
pose, a Gaussian jitter of it, cube poses drawn apart from each other, and (the instance-randomized
task) one object of each rigid object collection brought into focus at such a pose, per env.

All three take an env mask (``takes_env_mask``): they draw for every env and write the rows the mask
selects, so a reset inside the step has fixed shapes and no host read. The cubes are placed as Isaac
Lab places them, one by one, each retried until it is far enough from those placed, but with a fixed
number of draws for all envs at once (``max_sample_tries``, 128 here where Isaac Lab loops up to 5000
per env). With the stack task's ranges, none of 200,000 layouts kept two cubes closer than the 10 cm
asked; with 64 draws 41 did, 18 of them closer than a cube's edge (measured on the CPU). Only the
positions are retried (the angles never decide), squared gaps against the cubes placed: the cube event
takes 1.5 ms at 64 envs inside the CPU env (it took 3.7-5.6 ms drawing whole poses and norms). Torch's
own threads make any such sampler slow on a busy 2-core machine (60-190 ms a call with 2 threads), which
is why the CPU backend gives torch one thread.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils
from simlab.managers import SceneEntityCfg
from simlab.utils.env_mask import is_mask, takes_env_mask

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv

__all__ = [
    "randomize_joint_by_gaussian_offset",
    "randomize_object_pose",
    "randomize_rigid_objects_in_focus",
    "sample_object_poses",
    "set_default_joint_pose",
]

_ROBOT = SceneEntityCfg("robot")
_POSE_KEYS = ("x", "y", "z", "roll", "pitch", "yaw")
PARK_SPACING = 0.25
"""Gap [m] along x between the objects parked out of focus in one env (see randomize_rigid_objects_in_focus)."""


def _rows_and_targets(env: ManagerBasedEnv, env_ids) -> tuple[torch.Tensor | slice, torch.Tensor]:
    """(rows to compute, envs to write): all rows for a mask (written where it is set), else the ids."""
    if is_mask(env_ids):
        return slice(None), env_ids
    if env_ids is None:
        env_ids = torch.arange(env.num_envs, device=env.device)
    return env_ids, env_ids


@takes_env_mask
def set_default_joint_pose(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor,
    default_pose: list[float],
    asset_cfg: SceneEntityCfg = _ROBOT,
) -> None:
    """Make ``default_pose`` (one value per joint) the robot's default joint positions in every env."""
    asset = env.scene[asset_cfg.name]
    pose = math_utils.constant_tensor(default_pose, env.device)
    if pose.shape[0] != asset.num_joints:
        raise ValueError(
            f"default_pose has {pose.shape[0]} values; the robot has {asset.num_joints} joints {asset.joint_names}."
        )
    asset.data.default_joint_pos[:] = pose


@takes_env_mask
def randomize_joint_by_gaussian_offset(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor,
    mean: float,
    std: float,
    asset_cfg: SceneEntityCfg = _ROBOT,
) -> None:
    """Default joint positions plus Gaussian offsets, clamped to the soft limits, the last two joints
    (the gripper) left at their default; written as the state and the position target."""
    rows, targets = _rows_and_targets(env, env_ids)
    asset = env.scene[asset_cfg.name]
    default = asset.data.default_joint_pos[rows]
    pos = default + math_utils.sample_gaussian(mean, std, tuple(default.shape), env.device)
    limits = asset.data.soft_joint_pos_limits[rows]
    pos = pos.clamp(limits[..., 0], limits[..., 1])
    pos[:, -2:] = default[:, -2:]
    vel = asset.data.default_joint_vel[rows]
    asset.set_joint_position_target(pos, env_ids=targets)
    asset.set_joint_velocity_target(vel, env_ids=targets)
    asset.write_joint_state_to_sim(pos, vel, env_ids=targets)


def sample_object_poses(
    num_envs: int,
    num_objects: int,
    min_separation: float,
    pose_range: dict[str, tuple[float, float]],
    max_sample_tries: int,
    device: torch.device | str,
) -> torch.Tensor:
    """(num_envs, num_objects, 6) poses (x, y, z, roll, pitch, yaw) drawn one object after the other:
    each position the first of ``max_sample_tries`` draws at least ``min_separation`` [m] from the
    objects already placed (the last draw where none is), as Isaac Lab's sampler, for all envs at once.
    Only positions are retried: a pose's angles do not decide whether it is kept, so one draw each."""
    unknown = [key for key in pose_range if key not in _POSE_KEYS]
    if unknown:
        raise ValueError(f"pose_range has unknown key(s) {unknown}; allowed: {list(_POSE_KEYS)}")
    # a range's first two numbers are its bounds (Isaac Lab's yaw range is written (-1.0, 1, 0))
    bounds = math_utils.constant_tensor([tuple(pose_range.get(k, (0.0, 0.0)))[:2] for k in _POSE_KEYS], device)
    low, span = bounds[:, 0], bounds[:, 1] - bounds[:, 0]
    poses = low + span * torch.rand(num_envs, num_objects, 6, device=device)
    rows = torch.arange(num_envs, device=device)
    for i in range(1, num_objects):
        draws = low[:3] + span[:3] * torch.rand(num_envs, max_sample_tries, 3, device=device)
        squared_gaps = (draws[:, :, None, :] - poses[:, None, :i, :3]).square().sum(dim=-1)  # (envs, tries, i)
        apart = (squared_gaps > min_separation**2).all(dim=-1)
        # argmax finds the first True; where there is none, the last draw
        first = torch.where(apart.any(dim=1), apart.int().argmax(dim=1), max_sample_tries - 1)
        poses[:, i, :3] = draws[rows, first]
    return poses


@takes_env_mask
def randomize_object_pose(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor,
    asset_cfgs: list[SceneEntityCfg],
    min_separation: float = 0.0,
    pose_range: dict[str, tuple[float, float]] | None = None,
    max_sample_tries: int = 128,
) -> None:
    """Place the objects of ``asset_cfgs`` at poses drawn from ``pose_range`` (env frame), at least
    ``min_separation`` [m] apart, at rest."""
    rows, targets = _rows_and_targets(env, env_ids)
    origins = env.scene.env_origins[rows]
    poses = sample_object_poses(
        origins.shape[0], len(asset_cfgs), min_separation, pose_range or {}, max_sample_tries, env.device
    )
    for i, asset_cfg in enumerate(asset_cfgs):
        asset = env.scene[asset_cfg.name]
        quat = math_utils.quat_from_euler_xyz(poses[:, i, 3], poses[:, i, 4], poses[:, i, 5])
        asset.write_root_pose_to_sim(torch.cat([poses[:, i, :3] + origins, quat], dim=-1), env_ids=targets)
        asset.write_root_velocity_to_sim(torch.zeros(origins.shape[0], 6, device=env.device), env_ids=targets)


@takes_env_mask
def randomize_rigid_objects_in_focus(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor,
    asset_cfgs: list[SceneEntityCfg],
    out_focus_state: torch.Tensor,
    min_separation: float = 0.0,
    pose_range: dict[str, tuple[float, float]] | None = None,
    max_sample_tries: int = 128,
) -> None:
    """Per env, pick one object of each rigid object collection of ``asset_cfgs`` at random and place it
    at a pose drawn as ``randomize_object_pose`` draws (``min_separation`` [m] from the others' picks),
    at rest; park the others at ``out_focus_state`` (13 values: world position, quaternion w-x-y-z,
    velocities), where they fall away out of the task's reach.

    The picks go to ``env.rigid_objects_in_focus``, a ``(num_envs, len(asset_cfgs))`` tensor of object
    ids (Isaac Lab's list of lists, indexed the same way ``[env][k]``), and
    ``env.rigid_object_focus_columns`` maps a collection's name to its column, which the stack terms
    read (``object_pose_w``). Parallel worlds never collide, so every env parks at the same world
    point, as Isaac Lab's; within an env the parked objects are set ``PARK_SPACING`` apart along x,
    where Isaac Lab stacks them on one point.
    """
    rows, targets = _rows_and_targets(env, env_ids)
    origins = env.scene.env_origins[rows]
    n = origins.shape[0]
    poses = sample_object_poses(n, len(asset_cfgs), min_separation, pose_range or {}, max_sample_tries, env.device)
    focus = _focus_buffer(env, asset_cfgs)
    park = out_focus_state.to(device=env.device, dtype=torch.float32)
    parked = 0  # objects parked so far in an env, for their spacing
    for k, asset_cfg in enumerate(asset_cfgs):
        collection = env.scene[asset_cfg.name]
        m = collection.num_objects
        states = park.repeat(n, m, 1)
        states[..., 0] += PARK_SPACING * torch.arange(parked, parked + m, device=env.device)
        parked += m
        quat = math_utils.quat_from_euler_xyz(poses[:, k, 3], poses[:, k, 4], poses[:, k, 5])
        placed = torch.cat([poses[:, k, :3] + origins, quat, torch.zeros(n, 6, device=env.device)], dim=-1)
        chosen = torch.randint(m, (n,), device=env.device)
        in_focus = chosen[:, None] == torch.arange(m, device=env.device)  # (n, m)
        states = torch.where(in_focus[..., None], placed[:, None, :], states)
        collection.write_object_state_to_sim(states, env_ids=targets)
        if is_mask(targets):
            focus[:, k] = torch.where(targets, chosen, focus[:, k])
        else:
            focus[targets, k] = chosen


def _focus_buffer(env: ManagerBasedEnv, asset_cfgs: list[SceneEntityCfg]) -> torch.Tensor:
    """``env.rigid_objects_in_focus``, made on the first call (every collection's first object in focus)."""
    names = {cfg.name: k for k, cfg in enumerate(asset_cfgs)}
    if getattr(env, "rigid_object_focus_columns", None) != names:
        env.rigid_objects_in_focus = torch.zeros(env.num_envs, len(names), dtype=torch.long, device=env.device)
        env.rigid_object_focus_columns = names
    return env.rigid_objects_in_focus
