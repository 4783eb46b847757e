"""Event terms: ``func(env, env_ids, ...)``, for resets and domain randomization. Isaac Lab's names
and meanings.

Terms marked ``@takes_env_mask`` also accept a ``(num_envs,)`` bool mask as ``env_ids`` (draws for
every env, written where the mask is set): the event manager passes them the mask, so an env step
that uses only such terms has fixed shapes and replays as one CUDA graph. Other terms get ids.

Randomizations of physical properties change per-world MuJoCo model fields through
``env.sim.physics.model_field(...)`` (masses, inertias, frictions, gravity), so each env can have
its own. Distributions are ``"uniform"``, ``"log_uniform"`` or ``"gaussian"``; operations ``"add"``,
``"scale"`` (multiply the default value) or ``"abs"`` (replace it).
"""

from __future__ import annotations

import contextlib
import functools
import logging
import math
from typing import TYPE_CHECKING, Literal

import mujoco
import torch

import simlab.utils.math as math_utils
from simlab.managers import SceneEntityCfg
from simlab.managers.manager_base import ManagerTermBase
from simlab.utils.env_mask import host_read_when, is_mask, takes_env_mask

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv

logger = logging.getLogger(__name__)

_ROBOT = SceneEntityCfg("robot")
_POSE_KEYS = ("x", "y", "z", "roll", "pitch", "yaw")


def _ids(env: ManagerBasedEnv, env_ids) -> torch.Tensor:
    """The env ids as an index tensor: indexing with it gathers, so the result is already a copy."""
    if env_ids is None:
        return torch.arange(env.num_envs, device=env.device)
    return torch.as_tensor(env_ids, dtype=torch.long, device=env.device)


def _selection(env: ManagerBasedEnv, env_ids) -> tuple[torch.Tensor | slice, torch.Tensor]:
    """``(rows to compute, envs to write)``: for a bool mask, every row (draws for all envs, fixed
    shapes) written where the mask is set; for ids, those rows written to those envs."""
    if is_mask(env_ids):
        return slice(None), env_ids
    ids = _ids(env, env_ids)
    return ids, ids


def _rows(values: torch.Tensor, env_ids: torch.Tensor | slice, cols, fresh: bool = True) -> torch.Tensor:
    """``values[env_ids][:, cols]`` as a fresh tensor (``fresh=False``: possibly a view, for reading
    only), gathered in one kernel instead of two."""
    if isinstance(env_ids, slice):
        rows = values[env_ids, cols]
        return rows.clone() if fresh and isinstance(cols, slice) else rows  # a slice of a slice is a view
    if isinstance(cols, slice):
        return values[env_ids, cols]
    return values[env_ids[:, None], cols]


def _range_tensor(ranges: dict[str, tuple[float, float]], device) -> torch.Tensor:
    """(6, 2) low/high per pose key. Made once per config and device: a step being captured as a
    CUDA graph may not copy from the host, and the ranges never change."""
    unknown = [k for k in ranges if k not in _POSE_KEYS]
    if unknown:
        raise ValueError(f"unknown range key(s) {unknown}; allowed: {list(_POSE_KEYS)}")
    return math_utils.constant_tensor([ranges.get(k, (0.0, 0.0)) for k in _POSE_KEYS], device)


def _sample(distribution: str, params: tuple[float, float], shape, device) -> torch.Tensor:
    if distribution == "uniform":
        return math_utils.sample_uniform(params[0], params[1], shape, device)
    if distribution == "log_uniform":
        low, high = params
        if isinstance(low, (int, float)) and isinstance(high, (int, float)):  # checked here: no device read
            if low <= 0 or high <= 0:
                raise ValueError(f"log_uniform needs positive bounds, got {low} and {high}")
            return torch.exp(math_utils.sample_uniform(math.log(low), math.log(high), shape, device))
        return math_utils.sample_log_uniform(low, high, shape, device)
    if distribution == "gaussian":
        return math_utils.sample_gaussian(params[0], params[1], shape, device)
    raise ValueError(f"Unknown distribution '{distribution}'; allowed: 'uniform', 'log_uniform', 'gaussian'")


def _randomize(default: torch.Tensor, params: tuple[float, float], operation: str, distribution: str) -> torch.Tensor:
    """``default`` changed by a sample of ``distribution`` with ``operation``."""
    sample = _sample(distribution, params, tuple(default.shape), default.device)
    if operation == "add":
        return default + sample
    if operation == "scale":
        return default * sample
    if operation == "abs":
        return sample
    raise ValueError(f"Unknown operation '{operation}'; allowed: 'add', 'scale', 'abs'")


def _cols(ids, count: int, device) -> torch.Tensor:
    """Index tensor for a SceneEntityCfg id list or slice, made once per selection and device (a step
    captured as a CUDA graph may not copy from the host)."""
    if isinstance(ids, torch.Tensor):
        return ids.to(device=device, dtype=torch.long)
    key = (ids.start, ids.stop, ids.step) if isinstance(ids, slice) else tuple(int(i) for i in ids)
    return _index_tensor(isinstance(ids, slice), key, count, str(device))


@functools.lru_cache(maxsize=256)
def _index_tensor(is_slice: bool, key: tuple, count: int, device: str) -> torch.Tensor:
    if is_slice:
        return torch.arange(count, device=device)[slice(*key)]
    return torch.tensor(key, dtype=torch.long, device=device)


def _masked_write(target: torch.Tensor, mask: torch.Tensor, cols, values: torch.Tensor) -> None:
    """``target[:, cols] = values`` in the rows where ``mask`` is set (values for every row; fixed shapes)."""
    old = target[:, cols]
    target[:, cols] = torch.where(mask.view(-1, *([1] * (old.dim() - 1))), values, old)


# -- resets ----------------------------------------------------------------------------------------


def _only_keys(term: str, ranges: dict[str, tuple[float, float]], allowed: tuple[str, ...], why: str) -> None:
    unused = [k for k in ranges if k not in allowed]
    if unused:
        raise ValueError(f"{term}: pose_range key(s) {unused} are not used ({why}); allowed: {list(allowed)}")


def _write_root_state(asset, write_ids, positions, orientations, root, velocity_range, device) -> None:
    """Write the root poses, and the default root velocities plus uniform ``velocity_range`` offsets."""
    ranges = _range_tensor(velocity_range, device)
    velocities = root[:, 7:13] + math_utils.sample_uniform(ranges[:, 0], ranges[:, 1], (root.shape[0], 6), device)
    asset.write_root_pose_to_sim(torch.cat([positions, orientations], dim=-1), env_ids=write_ids)
    asset.write_root_velocity_to_sim(velocities, env_ids=write_ids)


@takes_env_mask
def reset_root_state_uniform(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor,
    pose_range: dict[str, tuple[float, float]],
    velocity_range: dict[str, tuple[float, float]],
    asset_cfg: SceneEntityCfg = _ROBOT,
) -> None:
    """Default root state (at the env origin) plus uniform offsets of position, orientation
    (roll/pitch/yaw, composed after the default) and velocity (all in the world frame)."""
    env_ids, write_ids = _selection(env, env_ids)
    asset = env.scene[asset_cfg.name]
    root = asset.data.default_root_state[env_ids]
    ranges = _range_tensor(pose_range, env.device)
    pose = math_utils.sample_uniform(ranges[:, 0], ranges[:, 1], (root.shape[0], 6), env.device)
    positions = root[:, 0:3] + env.scene.env_origins[env_ids] + pose[:, 0:3]
    delta = math_utils.quat_from_euler_xyz(pose[:, 3], pose[:, 4], pose[:, 5])
    orientations = math_utils.quat_mul(root[:, 3:7], delta)
    _write_root_state(asset, write_ids, positions, orientations, root, velocity_range, env.device)


@takes_env_mask
def reset_root_state_with_random_orientation(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor,
    pose_range: dict[str, tuple[float, float]],
    velocity_range: dict[str, tuple[float, float]],
    asset_cfg: SceneEntityCfg = _ROBOT,
) -> None:
    """Default root position (at the env origin) plus uniform offsets (``x``, ``y``, ``z``), an
    orientation drawn uniformly from all rotations, and the default velocity plus uniform offsets."""
    _only_keys("reset_root_state_with_random_orientation", pose_range, _POSE_KEYS[:3], "the orientation is uniform")
    env_ids, write_ids = _selection(env, env_ids)
    asset = env.scene[asset_cfg.name]
    root = asset.data.default_root_state[env_ids]
    ranges = _range_tensor(pose_range, env.device)
    offsets = math_utils.sample_uniform(ranges[:3, 0], ranges[:3, 1], (root.shape[0], 3), env.device)
    positions = root[:, 0:3] + env.scene.env_origins[env_ids] + offsets
    orientations = math_utils.random_orientation(root.shape[0], env.device)
    _write_root_state(asset, write_ids, positions, orientations, root, velocity_range, env.device)


@takes_env_mask
def reset_root_state_from_terrain(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor,
    pose_range: dict[str, tuple[float, float]],
    velocity_range: dict[str, tuple[float, float]],
    asset_cfg: SceneEntityCfg = _ROBOT,
) -> None:
    """The root at a random flat patch ``"init_pos"`` of the env's terrain tile (plus the default root
    position), turned by uniform ``roll``, ``pitch``, ``yaw``, with the default velocity plus uniform
    offsets. The terrain's sub-terrains must sample flat patches named ``init_pos``."""
    _only_keys("reset_root_state_from_terrain", pose_range, _POSE_KEYS[3:], "the position is a flat patch")
    terrain = env.scene.terrain
    patches = None if terrain is None else terrain.flat_patches.get("init_pos")
    if patches is None:
        found = [] if terrain is None else list(terrain.flat_patches)
        raise ValueError(
            "reset_root_state_from_terrain needs flat patches named 'init_pos' (FlatPatchSamplingCfg in the "
            f"sub-terrains' flat_patch_sampling); the terrain has {found}"
        )
    env_ids, write_ids = _selection(env, env_ids)
    asset = env.scene[asset_cfg.name]
    root = asset.data.default_root_state[env_ids]
    count = root.shape[0]
    pick = torch.randint(0, patches.shape[2], (count,), device=env.device)
    positions = patches[terrain.terrain_levels[env_ids], terrain.terrain_types[env_ids], pick] + root[:, 0:3]
    ranges = _range_tensor(pose_range, env.device)
    angles = math_utils.sample_uniform(ranges[3:, 0], ranges[3:, 1], (count, 3), env.device)
    orientations = math_utils.quat_from_euler_xyz(angles[:, 0], angles[:, 1], angles[:, 2])
    _write_root_state(asset, write_ids, positions, orientations, root, velocity_range, env.device)


def _write_joints(asset, env_ids: torch.Tensor, write_ids, joint_ids, pos: torch.Tensor, vel: torch.Tensor) -> None:
    limits = _rows(asset.data.soft_joint_pos_limits, env_ids, joint_ids, fresh=False)
    pos = pos.clamp(limits[..., 0], limits[..., 1])
    vel_limits = _rows(asset.data.soft_joint_vel_limits, env_ids, joint_ids, fresh=False)
    vel = vel.clamp(-vel_limits, vel_limits)
    asset.write_joint_state_to_sim(pos, vel, joint_ids=joint_ids, env_ids=write_ids)


@takes_env_mask
def reset_joints_by_scale(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor,
    position_range: tuple[float, float],
    velocity_range: tuple[float, float],
    asset_cfg: SceneEntityCfg = _ROBOT,
) -> None:
    """Default joint state multiplied by uniform factors, clamped to the soft limits."""
    env_ids, write_ids = _selection(env, env_ids)
    asset = env.scene[asset_cfg.name]
    ids = asset_cfg.joint_ids
    pos = _rows(asset.data.default_joint_pos, env_ids, ids, fresh=False)
    vel = _rows(asset.data.default_joint_vel, env_ids, ids, fresh=False)
    pos = pos * math_utils.sample_uniform(*position_range, tuple(pos.shape), env.device)
    vel = vel * math_utils.sample_uniform(*velocity_range, tuple(vel.shape), env.device)
    _write_joints(asset, env_ids, write_ids, ids, pos, vel)


@takes_env_mask
def reset_joints_by_offset(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor,
    position_range: tuple[float, float],
    velocity_range: tuple[float, float],
    asset_cfg: SceneEntityCfg = _ROBOT,
) -> None:
    """Default joint state plus uniform offsets, clamped to the soft limits."""
    env_ids, write_ids = _selection(env, env_ids)
    asset = env.scene[asset_cfg.name]
    ids = asset_cfg.joint_ids
    pos = _rows(asset.data.default_joint_pos, env_ids, ids, fresh=False)
    vel = _rows(asset.data.default_joint_vel, env_ids, ids, fresh=False)
    pos = pos + math_utils.sample_uniform(*position_range, tuple(pos.shape), env.device)
    vel = vel + math_utils.sample_uniform(*velocity_range, tuple(vel.shape), env.device)
    _write_joints(asset, env_ids, write_ids, ids, pos, vel)


@takes_env_mask
def reset_scene_to_default(env: ManagerBasedEnv, env_ids: torch.Tensor, reset_joint_targets: bool = False) -> None:
    """Every rigid object and articulation back to its default root (and joint) state."""
    env_ids, write_ids = _selection(env, env_ids)
    origins = env.scene.env_origins[env_ids]
    for asset in (*env.scene.rigid_objects.values(), *env.scene.articulations.values()):
        root = asset.data.default_root_state[env_ids].clone()
        root[:, 0:3] += origins
        asset.write_root_pose_to_sim(root[:, :7], env_ids=write_ids)
        asset.write_root_velocity_to_sim(root[:, 7:], env_ids=write_ids)
    for asset in env.scene.articulations.values():
        pos = asset.data.default_joint_pos[env_ids].clone()
        vel = asset.data.default_joint_vel[env_ids].clone()
        asset.write_joint_state_to_sim(pos, vel, env_ids=write_ids)
        if reset_joint_targets:
            asset.set_joint_position_target(pos, env_ids=write_ids)
            asset.set_joint_velocity_target(vel, env_ids=write_ids)


# -- disturbances ----------------------------------------------------------------------------------


@takes_env_mask
def push_by_setting_velocity(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor,
    velocity_range: dict[str, tuple[float, float]],
    asset_cfg: SceneEntityCfg = _ROBOT,
) -> None:
    """Add uniform random linear/angular velocities (world frame) to the root: a push."""
    env_ids, write_ids = _selection(env, env_ids)
    asset = env.scene[asset_cfg.name]
    vel = asset.data.root_vel_w[env_ids].clone()
    ranges = _range_tensor(velocity_range, env.device)
    vel += math_utils.sample_uniform(ranges[:, 0], ranges[:, 1], tuple(vel.shape), env.device)
    asset.write_root_velocity_to_sim(vel, env_ids=write_ids)


@takes_env_mask
def apply_external_force_torque(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor,
    force_range: tuple[float, float],
    torque_range: tuple[float, float],
    asset_cfg: SceneEntityCfg = _ROBOT,
) -> None:
    """Uniform random forces and torques (body frame) on the selected bodies, held until changed."""
    asset = env.scene[asset_cfg.name]
    if is_mask(env_ids) and not asset.permanent_wrench_composer.active and not any((*force_range, *torque_range)):
        return  # zero wrenches on a robot that has none: nothing changes (Isaac Lab's default ranges)
    env_ids, write_ids = _selection(env, env_ids)
    num_rows = env.num_envs if isinstance(env_ids, slice) else len(env_ids)
    num_bodies = len(asset_cfg.body_ids) if isinstance(asset_cfg.body_ids, list) else asset.num_bodies
    size = (num_rows, num_bodies, 3)
    forces = math_utils.sample_uniform(*force_range, size, env.device)
    torques = math_utils.sample_uniform(*torque_range, size, env.device)
    body_ids = None if isinstance(asset_cfg.body_ids, slice) else asset_cfg.body_ids
    asset.set_external_force_and_torque(forces, torques, body_ids=body_ids, env_ids=write_ids)


# -- physical properties ---------------------------------------------------------------------------


def _model_body_ids(asset, body_ids: slice | list[int]) -> list[int]:
    """The MuJoCo body ids of the asset's selected bodies (on the host)."""
    local = range(asset.num_bodies)[body_ids] if isinstance(body_ids, slice) else body_ids
    return [int(asset._body_ids[i]) for i in local]


def _free_bodies(model: mujoco.MjModel, ids: list[int]) -> bool:
    """Whether every body is free on its own: a free joint to the world and no children."""
    return all(
        model.body_parentid[b] == 0
        and model.body_jntnum[b] == 1
        and model.jnt_type[model.body_jntadr[b]] == mujoco.mjtJoint.mjJNT_FREE
        and not (model.body_parentid[1:] == b).any()
        for b in ids
    )


def _mass_host_read(env: ManagerBasedEnv, params: dict) -> str | None:
    """``randomize_rigid_body_mass`` by mask reads the host for articulated bodies (MuJoCo's set_const)."""
    asset_cfg = params["asset_cfg"]
    if _free_bodies(env.sim.model, _model_body_ids(env.scene[asset_cfg.name], asset_cfg.body_ids)):
        return None
    return (
        f"randomizes the masses of articulated bodies of '{asset_cfg.name}': MuJoCo's set_const runs for"
        " the selected envs (a host read); only free bodies (a rigid object) are randomized inside the step"
    )


def _set_const(env: ManagerBasedEnv, env_ids: torch.Tensor) -> None:
    """Let derived model constants follow edited masses (the GPU backend keeps its own)."""
    with contextlib.suppress(NotImplementedError):
        env.sim.physics.set_const(env_ids)


@takes_env_mask
@host_read_when(_mass_host_read)
def randomize_rigid_body_mass(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor | None,
    asset_cfg: SceneEntityCfg,
    mass_distribution_params: tuple[float, float],
    operation: Literal["add", "scale", "abs"],
    distribution: Literal["uniform", "log_uniform", "gaussian"] = "uniform",
    recompute_inertia: bool = True,
) -> None:
    """Per-env body masses from the default ones; inertias scale with the mass if ``recompute_inertia``.

    MuJoCo's constants derived from the masses (``body_subtreemass``, ``body_invweight0``,
    ``dof_invweight0``) follow: for free bodies of their own (no parent but the world, no children,
    such as a rigid object) they scale with the mass, as ``mj_setConst`` finds, inside the step (the
    world body's total mass, which no dynamics reads, is left as is); for
    articulated bodies MuJoCo's ``set_const`` runs, which reads the selected envs back to the host
    (a step that randomizes an articulation's masses by mask is not captured as a CUDA graph). The
    solver's tolerance scale ``stat.meaninertia`` keeps the model's value.
    """
    asset = env.scene[asset_cfg.name]
    physics = env.sim.physics
    local = _cols(asset_cfg.body_ids, asset.num_bodies, env.device)
    bodies = asset._body_index[local]
    if is_mask(env_ids):  # every env drawn, written where the mask is set: fixed shapes
        default = _rows(asset.data.default_mass, slice(None), local)
        masses = _randomize(default, mass_distribution_params, operation, distribution).clamp(min=1e-6)
        _masked_write(physics.model_field("body_mass"), env_ids, bodies, masses)
        ratio = masses / default.clamp(min=1e-9)
        if recompute_inertia:
            inertia = _rows(asset.data.default_inertia, slice(None), local) * ratio[..., None]
            _masked_write(physics.model_field("body_inertia"), env_ids, bodies, inertia)
        _scale_mass_constants(env, env_ids, asset, asset_cfg.body_ids, bodies, ratio, recompute_inertia)
        return
    env_ids = _ids(env, env_ids)
    default = _rows(asset.data.default_mass, env_ids, local)
    masses = _randomize(default, mass_distribution_params, operation, distribution).clamp(min=1e-6)
    body_mass = physics.model_field("body_mass")
    body_mass[env_ids[:, None], bodies] = masses
    if recompute_inertia:
        ratio = masses / default.clamp(min=1e-9)
        inertia = _rows(asset.data.default_inertia, env_ids, local) * ratio[..., None]
        physics.model_field("body_inertia")[env_ids[:, None], bodies] = inertia
    _set_const(env, env_ids)


def _scale_mass_constants(env, mask, asset, body_ids, bodies, ratio, scaled_inertia: bool) -> None:
    """The derived constants after masses (and inertias, if ``scaled_inertia``) were scaled by ``ratio``
    (envs, bodies) where ``mask`` is set; see ``randomize_rigid_body_mass``."""
    model, physics = env.sim.model, env.sim.physics
    ids = _model_body_ids(asset, body_ids)
    if not _free_bodies(model, ids):  # articulated bodies: MuJoCo's set_const, for the selected envs (a host read)
        _set_const(env, mask.nonzero().flatten())
        return
    device = env.device
    subtree = _model_constant(model, "body_subtreemass", ids, device)
    _masked_write(physics.model_field("body_subtreemass"), mask, bodies, subtree * ratio)
    # the free joint's translation weighs 1/m, its rotation 1/I: both scale with 1/ratio (rotation only
    # if the inertia was scaled too)
    keep = torch.ones_like(ratio)
    body_scale = torch.stack((ratio, ratio if scaled_inertia else keep), dim=-1)  # (envs, bodies, 2)
    invweight = _model_constant(model, "body_invweight0", ids, device)
    _masked_write(physics.model_field("body_invweight0"), mask, bodies, invweight / body_scale)
    dofs = [int(model.body_dofadr[b]) + k for b in ids for k in range(6)]
    dof_scale = body_scale.repeat_interleave(3, dim=-1).reshape(ratio.shape[0], len(dofs))
    dof_invweight = _model_constant(model, "dof_invweight0", dofs, device)
    _masked_write(physics.model_field("dof_invweight0"), mask, _index_tensor(False, tuple(dofs), 0, str(device)),
                  dof_invweight / dof_scale)  # fmt: skip


def _model_constant(model: mujoco.MjModel, field: str, rows: list[int], device) -> torch.Tensor:
    """The compiled model's ``field`` rows, as a float32 device tensor made once."""
    return math_utils.constant_tensor(getattr(model, field)[rows].tolist(), device)


def randomize_rigid_body_com(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor | None,
    com_range: dict[str, tuple[float, float]],
    asset_cfg: SceneEntityCfg,
) -> None:
    """Per-env centre of mass of the selected bodies: the model's, moved by a uniform offset
    (``com_range`` keys ``x``, ``y``, ``z``, body frame), the same offset for every selected body
    of an env."""
    unknown = [k for k in com_range if k not in ("x", "y", "z")]
    if unknown:
        raise ValueError(f"randomize_rigid_body_com: unknown com_range key(s) {unknown}; allowed: x, y, z")
    env_ids = _ids(env, env_ids)
    asset = env.scene[asset_cfg.name]
    bodies = asset._body_index[_cols(asset_cfg.body_ids, asset.num_bodies, env.device)]
    ranges = torch.tensor([com_range.get(k, (0.0, 0.0)) for k in ("x", "y", "z")], device=env.device)
    offset = math_utils.sample_uniform(ranges[:, 0], ranges[:, 1], (len(env_ids), 3), env.device)
    default = torch.as_tensor(env.sim.model.body_ipos, dtype=torch.float32, device=env.device)[bodies]
    env.sim.physics.model_field("body_ipos")[env_ids[:, None], bodies] = default + offset[:, None, :]
    _set_const(env, env_ids)


class randomize_rigid_body_material(ManagerTermBase):  # noqa: N801 - Isaac Lab's name
    """Per-env friction of the asset's geoms, drawn from ``num_buckets`` sampled materials (takes a
    bool mask too: materials drawn for every env, written where it is set).

    MuJoCo has one sliding friction coefficient per geom (``geom_friction[..., 0]``): it takes the
    static friction sample. MuJoCo has no restitution coefficient; ``restitution_range`` is checked
    but has no effect (bounciness follows from ``geom_solref``).
    """

    def __init__(self, cfg, env: ManagerBasedEnv):
        super().__init__(cfg, env)
        asset_cfg: SceneEntityCfg = cfg.params["asset_cfg"]
        asset = env.scene[asset_cfg.name]
        geoms = _asset_geoms(env.sim.model, asset, asset_cfg)
        if not geoms:
            raise ValueError(
                f"randomize_rigid_body_material: asset '{asset_cfg.name}' has no geoms on the selected bodies"
            )
        self._geoms = torch.tensor(geoms, dtype=torch.long, device=env.device)

    takes_env_mask = True

    def __call__(
        self,
        env: ManagerBasedEnv,
        env_ids: torch.Tensor | None,
        static_friction_range: tuple[float, float],
        dynamic_friction_range: tuple[float, float],
        restitution_range: tuple[float, float],
        num_buckets: int,
        asset_cfg: SceneEntityCfg,
        make_consistent: bool = False,
    ) -> None:
        rows, write = _selection(env, env_ids)
        count = env.num_envs if isinstance(rows, slice) else len(rows)
        ranges = math_utils.constant_tensor(
            [static_friction_range, dynamic_friction_range, restitution_range], env.device
        )
        buckets = math_utils.sample_uniform(ranges[:, 0], ranges[:, 1], (num_buckets, 3), env.device)
        if make_consistent:
            buckets[:, 1] = torch.min(buckets[:, 0], buckets[:, 1])
        choice = torch.randint(0, num_buckets, (count, len(self._geoms)), device=env.device)
        friction = env.sim.physics.model_field("geom_friction")[..., 0]
        if is_mask(write):
            _masked_write(friction, write, self._geoms, buckets[choice, 0])
        else:
            friction[write[:, None], self._geoms] = buckets[choice, 0]


def _joint_values(current, default, env_ids, joints, params, operation, distribution, min_value=None):
    """``current`` of the selected envs (all for a slice), with the selected joints' values drawn
    around ``default``; a fresh tensor."""
    value = current.clone() if isinstance(env_ids, slice) else current[env_ids]
    sample = _randomize(_rows(default, env_ids, joints), params, operation, distribution)
    value[:, joints] = sample if min_value is None else sample.clamp(min=min_value)
    return value


@takes_env_mask
def randomize_actuator_gains(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor | None,
    asset_cfg: SceneEntityCfg,
    stiffness_distribution_params: tuple[float, float] | None = None,
    damping_distribution_params: tuple[float, float] | None = None,
    operation: Literal["add", "scale", "abs"] = "abs",
    distribution: Literal["uniform", "log_uniform", "gaussian"] = "uniform",
) -> None:
    """Per-env PD gains of the selected joints' actuators, from the default gains (takes a bool mask
    too: gains drawn for every env, written where it is set)."""
    rows, env_ids = _selection(env, env_ids)
    asset = env.scene[asset_cfg.name]
    joints = _cols(asset_cfg.joint_ids, asset.num_joints, env.device)
    data = asset.data
    if stiffness_distribution_params is not None:
        value = _joint_values(
            data.joint_stiffness,
            data.default_joint_stiffness,
            rows,
            joints,
            stiffness_distribution_params,
            operation,
            distribution,
        )
        asset.write_joint_stiffness_to_sim(value, env_ids=env_ids)
    if damping_distribution_params is not None:
        value = _joint_values(
            data.joint_damping,
            data.default_joint_damping,
            rows,
            joints,
            damping_distribution_params,
            operation,
            distribution,
        )
        asset.write_joint_damping_to_sim(value, env_ids=env_ids)


class randomize_joint_parameters(ManagerTermBase):  # noqa: N801 - Isaac Lab's name
    """Per-env joint friction, armature and position limits, from the values at start-up.

    Takes a bool mask too (values drawn for every env, written where it is set). Given env ids, a
    draw that puts a lower limit above its upper one raises; given a mask (inside a step, with no
    read back to the host) the lower limit is held at the upper one instead. Armature changes need
    MuJoCo's ``set_const``, which reads a mask back to the host.
    """

    takes_env_mask = True

    @staticmethod
    def host_read(env: ManagerBasedEnv, params: dict) -> str | None:
        if params.get("armature_distribution_params") is None:
            return None
        return "randomizes joint armature: MuJoCo's set_const runs for the selected envs (a host read)"

    def __init__(self, cfg, env: ManagerBasedEnv):
        super().__init__(cfg, env)
        asset = env.scene[cfg.params["asset_cfg"].name]
        self._default_friction = asset.data.joint_friction_coeff.clone()
        self._default_armature = asset.data.joint_armature.clone()
        self._default_limits = asset.data.joint_pos_limits.clone()

    def __call__(
        self,
        env: ManagerBasedEnv,
        env_ids: torch.Tensor | None,
        asset_cfg: SceneEntityCfg,
        friction_distribution_params: tuple[float, float] | None = None,
        armature_distribution_params: tuple[float, float] | None = None,
        lower_limit_distribution_params: tuple[float, float] | None = None,
        upper_limit_distribution_params: tuple[float, float] | None = None,
        operation: Literal["add", "scale", "abs"] = "abs",
        distribution: Literal["uniform", "log_uniform", "gaussian"] = "uniform",
    ) -> None:
        rows, env_ids = _selection(env, env_ids)
        asset = env.scene[asset_cfg.name]
        joints = _cols(asset_cfg.joint_ids, asset.num_joints, env.device)
        data = asset.data
        if friction_distribution_params is not None:
            value = _joint_values(
                data.joint_friction_coeff,
                self._default_friction,
                rows,
                joints,
                friction_distribution_params,
                operation,
                distribution,
                min_value=0.0,
            )
            asset.write_joint_friction_coefficient_to_sim(value, env_ids=env_ids)
        if armature_distribution_params is not None:
            value = _joint_values(
                data.joint_armature,
                self._default_armature,
                rows,
                joints,
                armature_distribution_params,
                operation,
                distribution,
                min_value=0.0,
            )
            asset.write_joint_armature_to_sim(value, env_ids=env_ids)
            _set_const(env, env_ids.nonzero().flatten() if is_mask(env_ids) else env_ids)
        if lower_limit_distribution_params is not None or upper_limit_distribution_params is not None:
            limits = data.joint_pos_limits.clone() if isinstance(rows, slice) else data.joint_pos_limits[rows]
            default = self._default_limits if isinstance(rows, slice) else self._default_limits[rows]
            for col, params in ((0, lower_limit_distribution_params), (1, upper_limit_distribution_params)):
                if params is not None:
                    limits[:, joints, col] = _randomize(default[:, joints, col], params, operation, distribution)
            if is_mask(env_ids):
                limits[..., 0] = torch.minimum(limits[..., 0], limits[..., 1])
            elif bool((limits[..., 0] > limits[..., 1]).any()):
                raise ValueError("randomize_joint_parameters: a sampled lower joint limit exceeds the upper one")
            asset.write_joint_position_limit_to_sim(limits, env_ids=env_ids)


@takes_env_mask
def randomize_physics_scene_gravity(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor | None,
    gravity_distribution_params: tuple[list[float], list[float]],
    operation: Literal["add", "scale", "abs"],
    distribution: Literal["uniform", "log_uniform", "gaussian"] = "uniform",
) -> None:
    """Per-env gravity vector (``opt.gravity``) from the configured gravity ``cfg.sim.gravity``.

    Isaac Lab's PhysX scene has one gravity for all envs; every MuJoCo world has its own. Takes a
    bool mask too (drawn for every env, written where it is set)."""
    rows, env_ids = _selection(env, env_ids)
    count = env.num_envs if isinstance(rows, slice) else len(rows)
    default = math_utils.constant_tensor(env.cfg.sim.gravity, env.device).expand(count, 3)
    low = math_utils.constant_tensor(gravity_distribution_params[0], env.device)
    high = math_utils.constant_tensor(gravity_distribution_params[1], env.device)
    gravity = _randomize(default, (low, high), operation, distribution)
    field = env.sim.physics.model_field("opt.gravity")
    if is_mask(env_ids):
        field.copy_(torch.where(env_ids[:, None], gravity, field))
    else:
        field[env_ids] = gravity


class randomize_fixed_tendon_parameters(ManagerTermBase):  # noqa: N801 - Isaac Lab's name
    """Isaac Lab's randomization of PhysX fixed tendons (stiffness, damping, limits, rest length):
    accepted and ignored, with one note when the event manager builds it.

    simlab's models have no fixed tendons: where a robot's joints are coupled (the Shadow Hand's
    distal joints), MuJoCo equality constraints hold the coupling rigidly, with no tendon stiffness
    or damping to vary.
    """

    takes_env_mask = True  # it writes nothing

    def __init__(self, cfg, env: ManagerBasedEnv):
        super().__init__(cfg, env)
        asset_cfg = cfg.params.get("asset_cfg", _ROBOT)
        logger.warning(
            f"randomize_fixed_tendon_parameters on '{asset_cfg.name}' is ignored: simlab's models have no fixed"
            " tendons (coupled joints are MuJoCo equality constraints)"
        )

    def __call__(self, env: ManagerBasedEnv, env_ids, asset_cfg: SceneEntityCfg = _ROBOT, **kwargs) -> None:
        pass


# -- per-env shape and look (Isaac Lab's USD-level, 'prestartup' randomizations) -----------------------

_SCALABLE_GEOMS = {int(mujoco.mjtGeom.mjGEOM_BOX): "box", int(mujoco.mjtGeom.mjGEOM_ELLIPSOID): "ellipsoid"}


def _asset_geoms(model: mujoco.MjModel, asset, asset_cfg: SceneEntityCfg) -> list[int]:
    """The MuJoCo geoms on the selected bodies of ``asset``."""
    local = _cols(asset_cfg.body_ids, asset.num_bodies, "cpu").tolist()
    bodies = {int(asset._body_ids[i]) for i in local}
    return [g for g in range(model.ngeom) if int(model.geom_bodyid[g]) in bodies]


def _xyz_range(name: str, value: tuple[float, float] | dict[str, tuple[float, float]], keys: str) -> torch.Tensor:
    """(3, 2) low/high per key of ``keys``: one range for all, or a dict keyed by them (missing: 1)."""
    if isinstance(value, dict):
        unknown = [k for k in value if k not in keys]
        if unknown:
            raise ValueError(f"{name}: unknown key(s) {unknown}; allowed: {list(keys)}")
        return torch.tensor([value.get(k, (1.0, 1.0)) for k in keys], dtype=torch.float32)
    return torch.tensor([value] * 3, dtype=torch.float32)


def randomize_rigid_body_scale(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor | None,
    scale_range: tuple[float, float] | dict[str, tuple[float, float]],
    asset_cfg: SceneEntityCfg,
    relative_child_path: str | None = None,
) -> None:
    """Per-env scale of the asset's geoms: one uniform ``(x, y, z)`` sample per env scales their
    sizes, positions in the body and bounding volumes (per-world model fields), like Isaac Lab's
    scaling of the asset's USD prim. Masses and inertias keep their configured values.

    Box and ellipsoid geoms take any scale; other geom types are refused (a sphere scaled unevenly
    is no sphere). Applied once the model is compiled (at once if it already is), so it works as a
    ``prestartup`` term.
    """
    if relative_child_path is not None:
        raise ValueError("randomize_rigid_body_scale: relative_child_path names a USD prim; simlab scales every geom")
    ranges = _xyz_range("randomize_rigid_body_scale scale_range", scale_range, "xyz")

    def scale_geoms(sim) -> None:
        asset = env.scene[asset_cfg.name]
        geoms = _asset_geoms(sim.model, asset, asset_cfg)
        others = sorted({int(sim.model.geom_type[g]) for g in geoms} - set(_SCALABLE_GEOMS))
        if others:
            names = [mujoco.mjtGeom(t).name for t in others]
            raise ValueError(
                f"randomize_rigid_body_scale: asset '{asset_cfg.name}' has geoms of type {names};"
                f" only {list(_SCALABLE_GEOMS.values())} can be scaled per env"
            )
        ids = _ids(env, env_ids)
        low, high = ranges[:, 0].to(env.device), ranges[:, 1].to(env.device)
        scale = math_utils.sample_uniform(low, high, (len(ids), 3), env.device)[:, None, :]
        cols = torch.tensor(geoms, dtype=torch.long, device=env.device)
        physics = sim.physics
        for field in ("geom_size", "geom_pos"):
            default = torch.as_tensor(getattr(sim.model, field), dtype=torch.float32, device=env.device)[cols]
            physics.model_field(field)[ids[:, None], cols] = default * scale
        # the broad phase must still see the grown geom: bounding sphere and box grow with it
        rbound = torch.as_tensor(sim.model.geom_rbound, dtype=torch.float32, device=env.device)[cols]
        physics.model_field("geom_rbound")[ids[:, None], cols] = rbound * scale.amax(dim=-1)
        aabb = torch.as_tensor(sim.model.geom_aabb, dtype=torch.float32, device=env.device)[cols]
        physics.model_field("geom_aabb")[ids[:, None], cols] = aabb * scale.repeat(1, 1, 2)

    env.sim.add_reset_callback(scale_geoms)


def randomize_visual_color(
    env: ManagerBasedEnv,
    env_ids: torch.Tensor | None,
    colors: list[tuple[float, float, float]] | dict[str, tuple[float, float]],
    asset_cfg: SceneEntityCfg,
    mesh_name: str = "",
    event_name: str = "",
) -> None:
    """Per-env RGB color of the asset's geoms (per-world ``geom_rgba``): a uniform sample per channel
    from ``{"r": (lo, hi), "g": ..., "b": ...}``, or one of a list of colors. ``mesh_name`` and
    ``event_name`` name USD / Replicator objects and are not used. Applied once the model is compiled,
    so it works as a ``prestartup`` term.
    """
    if isinstance(colors, dict):
        ranges = _xyz_range("randomize_visual_color colors", colors, "rgb")
        palette = None
    else:
        palette = torch.tensor(colors, dtype=torch.float32)
        if palette.ndim != 2 or palette.shape[1] != 3 or len(palette) == 0:
            raise ValueError(
                f"randomize_visual_color: colors is a dict of r/g/b ranges or a list of RGB triples, got {colors!r}"
            )

    def color_geoms(sim) -> None:
        geoms = torch.tensor(_asset_geoms(sim.model, env.scene[asset_cfg.name], asset_cfg), device=env.device)
        ids = _ids(env, env_ids)
        if palette is None:
            low, high = ranges[:, 0].to(env.device), ranges[:, 1].to(env.device)
            rgb = math_utils.sample_uniform(low, high, (len(ids), 3), env.device)
        else:
            rgb = palette.to(env.device)[torch.randint(0, len(palette), (len(ids),), device=env.device)]
        sim.physics.model_field("geom_rgba")[ids[:, None], geoms, :3] = rgb[:, None, :]

    env.sim.add_reset_callback(color_geoms)
