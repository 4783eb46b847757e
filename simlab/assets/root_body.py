"""What rigid objects and articulations share: a root body, its bodies, and external wrenches.

Frames and conventions (Isaac Lab's): quaternions ``(w, x, y, z)``; the root state is
``(pos, quat, lin_vel, ang_vel)`` in the world frame, 13 numbers per env. MuJoCo's free joint keeps
its angular velocity in the body frame; the conversion happens here, on read and on write. A
fixed base is a mocap body: its pose can be written, its velocity is zero.
"""

from __future__ import annotations

from collections.abc import Callable

import mujoco
import torch

import simlab.utils.math as math_utils
from simlab.utils.env_mask import env_mask, is_mask, masked_copy_, rows
from simlab.utils.string import resolve_matching_names
from simlab.utils.wrench_composer import WrenchComposer

from .asset_base import AssetBase, EnvIds
from .body_properties_view import BodyPropertiesView


def contiguous(ids: list[int], device) -> slice | torch.Tensor:
    """A slice when ``ids`` are consecutive (so indexing gives a live view), else an index tensor."""
    if ids and ids == list(range(ids[0], ids[0] + len(ids))):
        return slice(ids[0], ids[0] + len(ids))
    return torch.tensor(ids, dtype=torch.long, device=device)


def breadth_first(model: mujoco.MjModel, ids: list[int], body_of) -> list[int]:
    """``ids`` (of bodies or joints) ordered as Isaac Lab orders an articulation's links and
    joints: by depth in the kinematic tree, then in model order (for a quadruped: the four hips,
    then the four thighs, then the four knees). MuJoCo's own order is depth first."""

    def depth(body: int) -> int:
        level = 0
        while body != 0:
            body, level = int(model.body_parentid[body]), level + 1
        return level

    return sorted(ids, key=lambda i: (depth(body_of(i)), i))


class RootedAsset(AssetBase):
    """Bodies named ``<Name>/...`` in the model, the first one being the root."""

    data: RootedAssetData

    def _initialize(self, sim) -> None:
        super()._initialize(sim)
        model, physics = sim.model, sim.physics
        self._physics = physics
        body_ids = breadth_first(
            model, [b for b in range(model.nbody) if model.body(b).name.startswith(self.prefix)], lambda b: b
        )
        if not body_ids:
            raise RuntimeError(f"'{self.cfg.prim_path}' has no bodies named '{self.prefix}...' in the model")
        self._body_ids = body_ids
        self._body_index = torch.tensor(body_ids, dtype=torch.long, device=self.device)
        self._body_names = [model.body(b).name[len(self.prefix) :] for b in body_ids]
        root = body_ids[0]
        self._root_body = root
        free = [
            j
            for j in range(model.njnt)
            if model.jnt_bodyid[j] == root and model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE
        ]
        self._mocap_id = int(model.body_mocapid[root])
        self._is_fixed_base = not free
        if free:
            qadr, dadr = int(model.jnt_qposadr[free[0]]), int(model.jnt_dofadr[free[0]])
            self._root_pos_cols, self._root_quat_cols = slice(qadr, qadr + 3), slice(qadr + 3, qadr + 7)
            self._root_lin_cols, self._root_ang_cols = slice(dadr, dadr + 3), slice(dadr + 3, dadr + 6)
        self._qpos, self._qvel = physics.data("qpos"), physics.data("qvel")
        if self._mocap_id >= 0:
            self._mocap_pos, self._mocap_quat = physics.data("mocap_pos"), physics.data("mocap_quat")
        self._xfrc_applied = physics.data("xfrc_applied")
        n = self.num_instances
        self.data = self._make_data(sim)
        # External wrenches, link frame: kept until changed, and for the next step only.
        self._permanent_wrench_composer = WrenchComposer(self)
        self._instantaneous_wrench_composer = WrenchComposer(self)
        self._wrench_written = False  # whether xfrc_applied holds a wrench that must be cleared
        init = self.cfg.init_state
        state = [*init.pos, *init.rot, *getattr(init, "lin_vel", (0, 0, 0)), *getattr(init, "ang_vel", (0, 0, 0))]
        self.data.default_root_state = torch.tensor(state, dtype=torch.float32, device=self.device).repeat(n, 1)
        self.data.body_names = self._body_names
        self.data.default_mass = torch.tensor(
            model.body_mass[body_ids], dtype=torch.float32, device=self.device
        ).repeat(n, 1)
        self.data.default_inertia = torch.tensor(
            model.body_inertia[body_ids], dtype=torch.float32, device=self.device
        ).repeat(n, 1, 1)

    def _make_data(self, sim) -> RootedAssetData:
        raise NotImplementedError

    # -- Isaac Lab's API --------------------------------------------------------------------------

    @property
    def num_bodies(self) -> int:
        return len(self._body_ids)

    @property
    def body_names(self) -> list[str]:
        return self._body_names

    @property
    def is_fixed_base(self) -> bool:
        return self._is_fixed_base

    @property
    def root_physx_view(self) -> BodyPropertiesView:
        """PhysX's view names for the bodies' masses and inertias (the state is in ``data``)."""
        view = self.__dict__.get("_properties_view")
        if view is None:
            view = self.__dict__["_properties_view"] = BodyPropertiesView(self)
        return view

    @property
    def _ALL_INDICES(self) -> torch.Tensor:  # noqa: N802 - Isaac Lab's name
        return torch.arange(self.num_instances, dtype=torch.long, device=self.device)

    def find_bodies(self, name_keys, preserve_order: bool = False) -> tuple[list[int], list[str]]:
        """Indices and names of the bodies matching names or regexes (errors list what exists)."""
        return resolve_matching_names(name_keys, self.body_names, preserve_order)

    @property
    def permanent_wrench_composer(self) -> WrenchComposer:
        """Wrenches applied every physics step until changed or reset (Isaac Lab's)."""
        return self._permanent_wrench_composer

    @property
    def instantaneous_wrench_composer(self) -> WrenchComposer:
        """Wrenches applied at the next physics step only, on top of the permanent ones (Isaac Lab's)."""
        return self._instantaneous_wrench_composer

    def reset(self, env_ids: EnvIds = None) -> None:
        for composer in (self._permanent_wrench_composer, self._instantaneous_wrench_composer):
            if composer.active:  # else zero already: no kernels for nothing
                composer.reset(None if env_ids is None else env_mask(env_ids, self.num_instances, self.device))

    def write_data_to_sim(self) -> None:
        permanent, instantaneous = self._permanent_wrench_composer, self._instantaneous_wrench_composer
        if permanent.active or instantaneous.active:
            force, torque = permanent.composed_force, permanent.composed_torque
            if instantaneous.active:
                force, torque = force + instantaneous.composed_force, torque + instantaneous.composed_torque
                instantaneous.reset()
            quat = self.data.body_quat_w  # MuJoCo applies xfrc_applied at the centre of mass, world frame
            self._xfrc_applied[:, self._body_index, 0:3] = math_utils.quat_apply(quat, force)
            self._xfrc_applied[:, self._body_index, 3:6] = math_utils.quat_apply(quat, torque)
            self._wrench_written = True
        elif self._wrench_written:
            self._xfrc_applied[:, self._body_index] = 0.0
            self._wrench_written = False

    def write_root_state_to_sim(self, root_state: torch.Tensor, env_ids: EnvIds = None) -> None:
        self.write_root_pose_to_sim(root_state[:, :7], env_ids)
        self.write_root_velocity_to_sim(root_state[:, 7:], env_ids)

    def write_root_pose_to_sim(self, root_pose: torch.Tensor, env_ids: EnvIds = None) -> None:
        """Root position (world frame, env origin included) and quaternion (w, x, y, z)."""
        env = self._env_index(env_ids)
        self._check_rows(root_pose, 7, env, "root_pose")
        origins = self._sim.env_origins if is_mask(env) else self._sim.env_origins[env]
        self._write_root_pose(root_pose[:, :3] - origins, math_utils.normalize(root_pose[:, 3:7]), env)

    def write_root_pose_env_to_sim(self, root_pose: torch.Tensor, env_ids: EnvIds = None) -> None:
        """A root pose read as ``data.root_pose_env`` (position from the env origin, unit quaternion
        w, x, y, z), written back to the bit: the env's world coordinates themselves, not through
        the world frame, and the quaternion as given (normalizing a float32 unit quaternion again
        can change its last digit)."""
        env = self._env_index(env_ids)
        self._check_rows(root_pose, 7, env, "root_pose")
        self._write_root_pose(root_pose[:, :3], root_pose[:, 3:7], env)

    def _write_root_pose(self, pos: torch.Tensor, quat: torch.Tensor, env) -> None:
        if self._is_fixed_base:
            if self._mocap_id < 0:
                raise RuntimeError(f"'{self.cfg.prim_path}' is welded to the world; its pose cannot be written")
            self._write_cols(self._mocap_pos, self._mocap_id, env, pos)
            self._write_cols(self._mocap_quat, self._mocap_id, env, quat)
        else:
            self._write_cols(self._qpos, self._root_pos_cols, env, pos)
            self._write_cols(self._qpos, self._root_quat_cols, env, quat)
        self._physics.mark_stale(env)

    def write_root_velocity_to_sim(self, root_velocity: torch.Tensor, env_ids: EnvIds = None) -> None:
        """Root linear and angular velocity, both in the world frame."""
        if self._is_fixed_base:
            return
        env = self._env_index(env_ids)
        self._check_rows(root_velocity, 6, env, "root_velocity")
        quat = self._qpos[:, self._root_quat_cols] if is_mask(env) else self._qpos[env, self._root_quat_cols]
        ang_vel_b = math_utils.quat_apply_inverse(quat, root_velocity[:, 3:6])
        self._write_root_velocity(root_velocity[:, :3], ang_vel_b, env)

    def write_root_ang_vel_b_to_sim(
        self, ang_vel_b: torch.Tensor, env_ids: EnvIds = None, lin_vel_w: torch.Tensor | None = None
    ) -> None:
        """Root angular velocity in the root's frame (``data.root_ang_vel_b``): MuJoCo's free joint
        holds it so, and this writes it to the bit (through the world frame it rounds in float32).
        With ``lin_vel_w``, the linear velocity (world frame) too: a state's whole velocity in one write."""
        if self._is_fixed_base:
            return
        env = self._env_index(env_ids)
        self._check_rows(ang_vel_b, 3, env, "ang_vel_b")
        if lin_vel_w is not None:
            self._check_rows(lin_vel_w, 3, env, "lin_vel_w")
        self._write_root_velocity(lin_vel_w, ang_vel_b, env)

    def _write_root_velocity(self, lin_vel_w: torch.Tensor | None, ang_vel_b: torch.Tensor, env) -> None:
        # MuJoCo's free joint holds the linear velocity in the world frame, the angular in the body's
        if lin_vel_w is not None:
            self._write_cols(self._qvel, self._root_lin_cols, env, lin_vel_w)
        self._write_cols(self._qvel, self._root_ang_cols, env, ang_vel_b)
        self._physics.mark_stale(env)

    # Isaac Lab 2.x names for the same writes.
    write_root_link_pose_to_sim = write_root_pose_to_sim
    write_root_com_velocity_to_sim = write_root_velocity_to_sim
    write_root_link_velocity_to_sim = write_root_velocity_to_sim

    def set_external_force_and_torque(
        self,
        forces: torch.Tensor,
        torques: torch.Tensor,
        positions: torch.Tensor | None = None,
        body_ids=None,
        env_ids: EnvIds = None,
        is_global: bool = False,
    ) -> None:
        """Wrenches applied every physics step until changed: Isaac Lab 2.x's name for
        ``permanent_wrench_composer.set_forces_and_torques``. Shapes ``(envs, bodies, 3)``; body
        frame unless ``is_global``; ``positions`` are where the forces act (offsets from the link
        origin, or world points when ``is_global``)."""
        if isinstance(positions, (list, tuple, slice)) or (
            isinstance(positions, torch.Tensor) and positions.dtype in (torch.long, torch.int32)
        ):  # Isaac Lab < 2.2 took body_ids third
            positions, body_ids = None, positions
        composer = self._permanent_wrench_composer
        composer.set_forces_and_torques(forces, torques, positions, body_ids, env_ids, is_global)
        if not is_mask(env_ids) and not bool(composer.composed_force.any() or composer.composed_torque.any()):
            composer.reset()  # all zero: nothing to apply (host read only outside an env step)

    # -- helpers ----------------------------------------------------------------------------------

    def _check_rows(self, value: torch.Tensor, width: int, env, what: str) -> None:
        # A mask selects rows of values given for every env (fixed shapes); ids, rows of their own.
        n_rows = self.num_instances if isinstance(env, slice) or is_mask(env) else len(env)
        if value.ndim != 2 or value.shape[1] != width or value.shape[0] != n_rows:
            raise ValueError(
                f"{what} must have shape ({n_rows}, {width}) for the selected envs, got {tuple(value.shape)}"
            )

    @staticmethod
    def _write_cols(dst: torch.Tensor, cols, env_ids, values) -> None:
        """``dst[env_ids, cols] = values`` for env ids (rows of ``values`` per id), a bool mask
        (``values`` has a row per env; rows where the mask is clear keep their value), or None."""
        env = slice(None) if env_ids is None else env_ids
        if is_mask(env):
            mask = env.to(dst.device)
            if isinstance(cols, (slice, int)):  # a view: select in place
                masked_copy_(dst[:, cols], mask, values)
            else:
                old = dst[:, cols]
                dst[:, cols] = torch.where(rows(mask, old), torch.as_tensor(values, dtype=dst.dtype), old)
            return
        if not isinstance(env, (slice, torch.Tensor)):
            env = torch.as_tensor(list(env), dtype=torch.long, device=dst.device)
        if isinstance(env, torch.Tensor):
            env = env.to(device=dst.device, dtype=torch.long)
        if isinstance(env, torch.Tensor) and isinstance(cols, torch.Tensor):
            dst[env[:, None], cols] = values
        else:
            dst[env, cols] = values


class RootedAssetData:
    """Live views of an asset's state. Read every step; nothing here is cached.

    Joint and root states are MuJoCo's ``qpos``/``qvel`` themselves. Body poses and velocities
    are derived quantities: reading one first brings the worlds whose state changed since up to
    date (``PhysicsBackend.ensure_kinematics``), so they are always current and cost nothing when unread.
    """

    GRAVITY_VEC_W = None
    FORWARD_VEC_B = None

    def __init__(self, asset: RootedAsset, sim):
        self._asset = asset
        self._origins = sim.env_origins
        physics = sim.physics
        self._physics = physics
        dev = asset.device
        self._xpos, self._xquat, self._cvel = physics.data("xpos"), physics.data("xquat"), physics.data("cvel")
        self._xipos = physics.data("xipos")
        self._subtree_com = physics.data("subtree_com")
        self._rootids = torch.tensor(sim.model.body_rootid[asset._body_ids], dtype=torch.long, device=dev)
        gravity = torch.tensor(sim.model.opt.gravity, dtype=torch.float32, device=dev)
        norm = torch.linalg.norm(gravity)
        gravity = gravity / norm if norm > 0 else torch.tensor([0.0, 0.0, -1.0], device=dev)
        n = asset.num_instances
        self.GRAVITY_VEC_W = gravity.repeat(n, 1)
        self.FORWARD_VEC_B = torch.tensor([1.0, 0.0, 0.0], device=dev).repeat(n, 1)
        self.default_root_state: torch.Tensor
        self.body_names: list[str] = []
        self._per_state_values: dict[str, tuple[tuple[int, bool], torch.Tensor]] = {}

    def _per_state(self, name: str, compute: Callable[[], torch.Tensor]) -> torch.Tensor:
        """``compute()`` once per state of the simulation (``PhysicsBackend.state_version``): the
        quantities many terms read in one env step (base-frame velocities, projected gravity,
        heading) then cost their kernels once. The tensor is shared until the state changes: read
        it, do not write into it (as with Isaac Lab's data buffers)."""
        key = (self._physics.state_version, torch.is_inference_mode_enabled())
        cached = self._per_state_values.get(name)
        if cached is not None and cached[0] == key:
            return cached[1]
        value = compute()
        self._per_state_values[name] = (key, value)
        return value

    def _derived(self, field: torch.Tensor) -> torch.Tensor:
        """``field`` (a body pose or velocity MjData tensor) once it matches the current state (the
        backend's kinematics pass: no collision or constraint work for a pose)."""
        self._physics.ensure_kinematics()
        return field

    # root ------------------------------------------------------------------------------------------

    @property
    def root_pos_w(self) -> torch.Tensor:
        return self.root_pos_env + self._origins

    @property
    def root_pos_env(self) -> torch.Tensor:
        """Root position from the env origin: the coordinates of the env's own MuJoCo world, exact
        (``root_pos_w - env_origins`` rounds twice in float32). What a relative scene state holds."""
        a = self._asset
        if a._is_fixed_base:
            if a._mocap_id >= 0:
                return a._mocap_pos[:, a._mocap_id]
            return self._derived(self._xpos)[:, a._root_body]
        return a._qpos[:, a._root_pos_cols]

    @property
    def root_quat_w(self) -> torch.Tensor:
        a = self._asset
        if a._is_fixed_base:
            return a._mocap_quat[:, a._mocap_id] if a._mocap_id >= 0 else self._derived(self._xquat)[:, a._root_body]
        return a._qpos[:, a._root_quat_cols]

    @property
    def root_lin_vel_w(self) -> torch.Tensor:
        a = self._asset
        if a._is_fixed_base:
            return torch.zeros_like(self.GRAVITY_VEC_W)
        return a._qvel[:, a._root_lin_cols]

    @property
    def root_ang_vel_b(self) -> torch.Tensor:
        a = self._asset
        if a._is_fixed_base:
            return torch.zeros_like(self.GRAVITY_VEC_W)
        return a._qvel[:, a._root_ang_cols]

    @property
    def root_ang_vel_w(self) -> torch.Tensor:
        return self._per_state("root_ang_vel_w", lambda: math_utils.quat_apply(self.root_quat_w, self.root_ang_vel_b))

    @property
    def root_lin_vel_b(self) -> torch.Tensor:
        return self._per_state(
            "root_lin_vel_b", lambda: math_utils.quat_apply_inverse(self.root_quat_w, self.root_lin_vel_w)
        )

    @property
    def root_pose_w(self) -> torch.Tensor:
        return torch.cat([self.root_pos_w, self.root_quat_w], dim=-1)

    @property
    def root_pose_env(self) -> torch.Tensor:
        """Root position from the env origin (``root_pos_env``) and quaternion (w, x, y, z)."""
        return torch.cat([self.root_pos_env, self.root_quat_w], dim=-1)

    @property
    def root_vel_w(self) -> torch.Tensor:
        return torch.cat([self.root_lin_vel_w, self.root_ang_vel_w], dim=-1)

    @property
    def root_state_w(self) -> torch.Tensor:
        return torch.cat([self.root_pos_w, self.root_quat_w, self.root_lin_vel_w, self.root_ang_vel_w], dim=-1)

    @property
    def projected_gravity_b(self) -> torch.Tensor:
        return self._per_state(
            "projected_gravity_b", lambda: math_utils.quat_apply_inverse(self.root_quat_w, self.GRAVITY_VEC_W)
        )

    @property
    def heading_w(self) -> torch.Tensor:
        def heading() -> torch.Tensor:
            forward = math_utils.quat_apply(self.root_quat_w, self.FORWARD_VEC_B)
            return torch.atan2(forward[:, 1], forward[:, 0])

        return self._per_state("heading_w", heading)

    # Isaac Lab 2.x aliases: the root link is the root body's frame.
    root_link_pos_w = root_pos_w
    root_link_quat_w = root_quat_w
    root_link_pose_w = root_pose_w
    root_link_state_w = root_state_w
    root_com_lin_vel_w = root_lin_vel_w
    root_com_ang_vel_w = root_ang_vel_w
    root_com_lin_vel_b = root_lin_vel_b
    root_com_ang_vel_b = root_ang_vel_b
    root_com_vel_w = root_vel_w

    # bodies -----------------------------------------------------------------------------------------

    @property
    def body_pos_w(self) -> torch.Tensor:
        return self.body_pos_env + self._origins[:, None]

    @property
    def body_pos_env(self) -> torch.Tensor:
        """Body positions from the env origin (the env's own world, exact: see ``root_pos_env``)."""
        return self._derived(self._xpos)[:, self._asset._body_index]

    @property
    def body_quat_w(self) -> torch.Tensor:
        return self._derived(self._xquat)[:, self._asset._body_index]

    @property
    def body_ang_vel_w(self) -> torch.Tensor:
        return self._derived(self._cvel)[:, self._asset._body_index, 0:3]

    @property
    def body_lin_vel_w(self) -> torch.Tensor:
        # cvel's linear part is the velocity of the point at the kinematic tree's centre of mass.
        ids = self._asset._body_index
        self._physics.ensure_kinematics()
        offset = self._xpos[:, ids] - self._subtree_com[:, self._rootids]
        return self._cvel[:, ids, 3:6] + torch.cross(self._cvel[:, ids, 0:3], offset, dim=-1)

    @property
    def body_com_pos_w(self) -> torch.Tensor:
        return self._derived(self._xipos)[:, self._asset._body_index] + self._origins[:, None]

    @property
    def body_pose_w(self) -> torch.Tensor:
        return torch.cat([self.body_pos_w, self.body_quat_w], dim=-1)

    @property
    def body_vel_w(self) -> torch.Tensor:
        # body_lin_vel_w's and body_ang_vel_w's math from one gather of cvel
        ids = self._asset._body_index
        self._physics.ensure_kinematics()
        cvel = self._cvel[:, ids]
        offset = self._xpos[:, ids] - self._subtree_com[:, self._rootids]
        return torch.cat([cvel[..., 3:6] + torch.cross(cvel[..., 0:3], offset, dim=-1), cvel[..., 0:3]], dim=-1)

    @property
    def body_state_w(self) -> torch.Tensor:
        return torch.cat([self.body_pos_w, self.body_quat_w, self.body_lin_vel_w, self.body_ang_vel_w], dim=-1)

    body_link_pos_w = body_pos_w
    body_link_quat_w = body_quat_w
    body_link_pose_w = body_pose_w
    body_link_state_w = body_state_w
    body_com_lin_vel_w = body_lin_vel_w
    body_com_ang_vel_w = body_ang_vel_w

    @property
    def body_mass(self) -> torch.Tensor:
        return self._asset._physics.model_field("body_mass")[:, self._asset._body_index]
