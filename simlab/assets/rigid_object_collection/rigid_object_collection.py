"""Several rigid objects handled as one asset (Isaac Lab's ``RigidObjectCollection``).

Each object of the collection is a :class:`~simlab.assets.RigidObject` of its own (spawned, bound to
the model and written by the same code on either backend); the collection gives them Isaac Lab's
object axis: data of shape ``(num_envs, num_objects, ...)``, writers that take ``env_ids`` and
``object_ids``, and one pair of wrench composers over all objects.

Frames (Isaac Lab's): the *link* frame is the body's own frame, the *com* frame sits at its centre of
mass with the principal axes of inertia. ``object_state_w`` is the link pose with the com velocity;
``write_object_state_to_sim`` takes the same.
"""

from __future__ import annotations

import weakref
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import torch

import simlab.utils.math as math_utils
from simlab.sim import SimulationContext
from simlab.utils.env_mask import env_mask, is_mask
from simlab.utils.string import resolve_matching_names
from simlab.utils.wrench_composer import WrenchComposer

from ..asset_base import EnvIds
from ..rigid_object import RigidObject
from .rigid_object_collection_data import RigidObjectCollectionData

if TYPE_CHECKING:
    from .rigid_object_collection_cfg import RigidObjectCollectionCfg

ObjectIds = Sequence[int] | torch.Tensor | slice | None


class RigidObjectCollection:
    """Rigid objects with a shared object axis; see the module docstring."""

    def __init__(self, cfg: RigidObjectCollectionCfg):
        cfg.validate()
        if not cfg.rigid_objects:
            raise ValueError("RigidObjectCollectionCfg.rigid_objects is empty; give at least one RigidObjectCfg")
        from ..rigid_object import RigidObjectCfg

        for name, object_cfg in cfg.rigid_objects.items():
            if not isinstance(object_cfg, RigidObjectCfg):
                raise ValueError(
                    f"RigidObjectCollectionCfg.rigid_objects['{name}'] must be a RigidObjectCfg, got"
                    f" {type(object_cfg).__name__}"
                )
        self.cfg = cfg
        sim = SimulationContext.instance()
        if sim is None:
            raise RuntimeError("Create a SimulationContext before a RigidObjectCollection.")
        self._sim = sim
        self._is_initialized = False
        self._object_names = list(cfg.rigid_objects)
        self.rigid_objects: dict[str, RigidObject] = {
            name: RigidObject(object_cfg) for name, object_cfg in cfg.rigid_objects.items()
        }
        # a weak callback: the simulation must not keep a collection alive (Isaac Lab's tests count references)
        this = weakref.ref(self)
        sim.add_reset_callback(lambda s: this() is not None and this()._initialize(s))

    def _initialize(self, sim: SimulationContext) -> None:
        objects = list(self.rigid_objects.values())
        self._objects = objects
        self._root_bodies = torch.tensor([o._root_body for o in objects], dtype=torch.long, device=self.device)
        self._xfrc_applied = sim.physics.data("xfrc_applied")
        self.data = RigidObjectCollectionData(self, sim)
        self._permanent_wrench_composer = WrenchComposer(self)
        self._instantaneous_wrench_composer = WrenchComposer(self)
        self._wrench_written = False
        self._is_initialized = True

    # -- Isaac Lab's properties -------------------------------------------------------------------

    @property
    def is_initialized(self) -> bool:
        return self._is_initialized

    @property
    def device(self) -> str:
        return self._sim.device

    @property
    def num_instances(self) -> int:
        return self._sim.num_envs

    @property
    def num_objects(self) -> int:
        return len(self._object_names)

    @property
    def object_names(self) -> list[str]:
        return self._object_names

    # Isaac Lab 3.0's names: the objects are the collection's bodies
    num_bodies = num_objects
    body_names = object_names

    @property
    def _ALL_ENV_INDICES(self) -> torch.Tensor:  # noqa: N802 - Isaac Lab's name
        return torch.arange(self.num_instances, dtype=torch.long, device=self.device)

    @property
    def _ALL_OBJ_INDICES(self) -> torch.Tensor:  # noqa: N802 - Isaac Lab's name
        return torch.arange(self.num_objects, dtype=torch.long, device=self.device)

    @property
    def root_physx_view(self) -> Any:
        raise AttributeError(
            "RigidObjectCollection.root_physx_view is PhysX's view of all objects; simlab has none. Read the state"
            " from collection.data, the masses from collection.data.default_mass, and read or write one object's"
            " masses with collection.rigid_objects[name].root_physx_view.get_masses() / set_masses()"
        )

    @property
    def permanent_wrench_composer(self) -> WrenchComposer:
        """Wrenches ``(num_envs, num_objects, 3)`` applied every physics step until changed (Isaac Lab's)."""
        return self._permanent_wrench_composer

    @property
    def instantaneous_wrench_composer(self) -> WrenchComposer:
        """Wrenches applied at the next physics step only, on top of the permanent ones (Isaac Lab's)."""
        return self._instantaneous_wrench_composer

    def find_objects(self, name_keys: str | Sequence[str], preserve_order: bool = False) -> tuple[list[int], list[str]]:
        """Indices and names of the objects matching names or regexes (errors list what exists)."""
        return resolve_matching_names(name_keys, self.object_names, preserve_order)

    find_bodies = find_objects

    def _env_obj_ids_to_view_ids(self, env_ids: torch.Tensor, object_ids: torch.Tensor) -> torch.Tensor:
        """Isaac Lab's flat index of (env, object) pairs, objects major (``object * num_envs + env``),
        in env-major order: the row a pair has when the collection's per-object data is laid end to end."""
        env_ids = torch.as_tensor(env_ids, dtype=torch.long, device=self.device).flatten()
        object_ids = torch.as_tensor(object_ids, dtype=torch.long, device=self.device).flatten()
        return (object_ids[None, :] * self.num_instances + env_ids[:, None]).flatten()

    # -- life cycle -------------------------------------------------------------------------------

    def reset(self, env_ids: EnvIds = None, object_ids: ObjectIds = None) -> None:
        """Clear the external wrenches of ``env_ids`` (ids or a bool mask) on ``object_ids`` (None: all)."""
        for composer in (self._permanent_wrench_composer, self._instantaneous_wrench_composer):
            if not composer.active:
                continue  # zero already: no kernels for nothing
            if object_ids is None or (isinstance(object_ids, slice) and object_ids == slice(None)):
                composer.reset(None if env_ids is None else env_mask(env_ids, self.num_instances, self.device))
                continue
            ids = self._object_list(object_ids)
            rows = self.num_instances if env_ids is None or is_mask(env_ids) else len(env_ids)
            zeros = torch.zeros(rows, len(ids), 3, device=self.device)
            composer.set_forces_and_torques(zeros, zeros, body_ids=ids, env_ids=env_ids)

    def restart(self, mask: torch.Tensor) -> None:
        """Nothing derived from the worlds' state is kept here (``InteractiveScene.restart``)."""

    def update(self, dt: float) -> None:
        for rigid_object in self.rigid_objects.values():
            rigid_object.update(dt)

    def write_data_to_sim(self) -> None:
        """Apply the composed wrenches (MuJoCo's ``xfrc_applied``: world frame, at the centre of mass)."""
        permanent, instantaneous = self._permanent_wrench_composer, self._instantaneous_wrench_composer
        if permanent.active or instantaneous.active:
            force, torque = permanent.composed_force, permanent.composed_torque
            if instantaneous.active:
                force, torque = force + instantaneous.composed_force, torque + instantaneous.composed_torque
                instantaneous.reset()
            quat = self.data.object_link_quat_w
            self._xfrc_applied[:, self._root_bodies, 0:3] = math_utils.quat_apply(quat, force)
            self._xfrc_applied[:, self._root_bodies, 3:6] = math_utils.quat_apply(quat, torque)
            self._wrench_written = True
        elif self._wrench_written:
            self._xfrc_applied[:, self._root_bodies] = 0.0
            self._wrench_written = False

    def set_external_force_and_torque(
        self,
        forces: torch.Tensor,
        torques: torch.Tensor,
        positions: torch.Tensor | None = None,
        object_ids: ObjectIds = None,
        env_ids: EnvIds = None,
        is_global: bool = False,
    ) -> None:
        """Wrenches applied every physics step until changed (Isaac Lab 2.x's name for
        ``permanent_wrench_composer.set_forces_and_torques``), shapes ``(envs, objects, 3)``."""
        object_ids = None if object_ids is None else self._object_list(object_ids)
        self._permanent_wrench_composer.set_forces_and_torques(
            forces, torques, positions, object_ids, env_ids, is_global
        )

    # -- writers ----------------------------------------------------------------------------------

    def write_object_state_to_sim(
        self, object_state: torch.Tensor, env_ids: EnvIds = None, object_ids: ObjectIds = None
    ):
        """``(envs, objects, 13)``: link pose (pos, quat w-x-y-z) and com velocity (lin, ang), world frame."""
        self.write_object_link_pose_to_sim(object_state[..., :7], env_ids, object_ids)
        self.write_object_com_velocity_to_sim(object_state[..., 7:], env_ids, object_ids)

    def write_object_link_state_to_sim(self, object_state: torch.Tensor, env_ids: EnvIds = None, object_ids=None):
        """``(envs, objects, 13)``: link pose and link velocity, world frame."""
        self.write_object_link_pose_to_sim(object_state[..., :7], env_ids, object_ids)
        self.write_object_link_velocity_to_sim(object_state[..., 7:], env_ids, object_ids)

    def write_object_com_state_to_sim(self, object_state: torch.Tensor, env_ids: EnvIds = None, object_ids=None):
        """``(envs, objects, 13)``: com pose and com velocity, world frame."""
        self.write_object_com_pose_to_sim(object_state[..., :7], env_ids, object_ids)
        self.write_object_com_velocity_to_sim(object_state[..., 7:], env_ids, object_ids)

    def write_object_link_pose_to_sim(self, object_pose: torch.Tensor, env_ids: EnvIds = None, object_ids=None):
        """``(envs, objects, 7)`` link poses (position with the env origin, quaternion w-x-y-z)."""
        for pose, rigid_object in self._selected(object_pose, 7, env_ids, object_ids, "object_pose"):
            rigid_object.write_root_pose_to_sim(pose, env_ids)

    write_object_pose_to_sim = write_object_link_pose_to_sim

    def write_object_com_pose_to_sim(self, object_pose: torch.Tensor, env_ids: EnvIds = None, object_ids=None):
        """``(envs, objects, 7)`` centre-of-mass poses; written as the link poses that put the com there."""
        for com_pose, rigid_object in self._selected(object_pose, 7, env_ids, object_ids, "object_pose"):
            com_pos_b, com_quat_b = self.data._com_offset(rigid_object)
            link_quat = math_utils.quat_mul(
                com_pose[:, 3:7], math_utils.quat_conjugate(com_quat_b).expand_as(com_pose[:, 3:7])
            )
            link_pos = com_pose[:, :3] - math_utils.quat_apply(link_quat, com_pos_b.expand_as(com_pose[:, :3]))
            rigid_object.write_root_pose_to_sim(torch.cat([link_pos, link_quat], dim=-1), env_ids)

    def write_object_link_velocity_to_sim(self, object_velocity: torch.Tensor, env_ids: EnvIds = None, object_ids=None):
        """``(envs, objects, 6)`` velocities of the link frames' origins (lin, ang), world frame."""
        for velocity, rigid_object in self._selected(object_velocity, 6, env_ids, object_ids, "object_velocity"):
            rigid_object.write_root_velocity_to_sim(velocity, env_ids)

    def write_object_com_velocity_to_sim(self, object_velocity: torch.Tensor, env_ids: EnvIds = None, object_ids=None):
        """``(envs, objects, 6)`` velocities of the centres of mass (lin, ang), world frame: MuJoCo's free
        joint moves the link origin, so the linear part is moved there (v_link = v_com - w x r)."""
        for velocity, rigid_object in self._selected(object_velocity, 6, env_ids, object_ids, "object_velocity"):
            com_pos_b, _ = self.data._com_offset(rigid_object)
            quat = rigid_object.data.root_quat_w
            env = rigid_object._env_index(env_ids)
            quat = quat if isinstance(env, slice) or is_mask(env) else quat[env]
            lever = math_utils.quat_apply(quat, com_pos_b.expand(len(quat), 3))
            link_lin = velocity[:, :3] - torch.linalg.cross(velocity[:, 3:6], lever, dim=-1)
            rigid_object.write_root_velocity_to_sim(torch.cat([link_lin, velocity[:, 3:6]], dim=-1), env_ids)

    write_object_velocity_to_sim = write_object_com_velocity_to_sim

    # Isaac Lab 3.0's names for the same writes (``body_ids`` are object ids)
    def write_body_state_to_sim(self, body_states: torch.Tensor, env_ids: EnvIds = None, body_ids=None) -> None:
        self.write_object_state_to_sim(body_states, env_ids, body_ids)

    def write_body_link_state_to_sim(self, body_states: torch.Tensor, env_ids: EnvIds = None, body_ids=None) -> None:
        self.write_object_link_state_to_sim(body_states, env_ids, body_ids)

    def write_body_com_state_to_sim(self, body_states: torch.Tensor, env_ids: EnvIds = None, body_ids=None) -> None:
        self.write_object_com_state_to_sim(body_states, env_ids, body_ids)

    def write_body_link_pose_to_sim(self, body_poses: torch.Tensor, env_ids: EnvIds = None, body_ids=None) -> None:
        self.write_object_link_pose_to_sim(body_poses, env_ids, body_ids)

    write_body_pose_to_sim = write_body_link_pose_to_sim

    def write_body_com_pose_to_sim(self, body_poses: torch.Tensor, env_ids: EnvIds = None, body_ids=None) -> None:
        self.write_object_com_pose_to_sim(body_poses, env_ids, body_ids)

    def write_body_com_velocity_to_sim(self, body_vels: torch.Tensor, env_ids: EnvIds = None, body_ids=None) -> None:
        self.write_object_com_velocity_to_sim(body_vels, env_ids, body_ids)

    write_body_velocity_to_sim = write_body_com_velocity_to_sim

    def write_body_link_velocity_to_sim(self, body_vels: torch.Tensor, env_ids: EnvIds = None, body_ids=None) -> None:
        self.write_object_link_velocity_to_sim(body_vels, env_ids, body_ids)

    # -- helpers ----------------------------------------------------------------------------------

    def _object_list(self, object_ids: ObjectIds) -> list[int]:
        """Object ids as a list (a tensor is read to the host: give lists inside an env step)."""
        if object_ids is None or (isinstance(object_ids, slice) and object_ids == slice(None)):
            return list(range(self.num_objects))
        if isinstance(object_ids, slice):
            return list(range(self.num_objects))[object_ids]
        ids = [int(i) for i in (object_ids.flatten().tolist() if isinstance(object_ids, torch.Tensor) else object_ids)]
        bad = [i for i in ids if not 0 <= i < self.num_objects]
        if bad:
            raise IndexError(
                f"object_ids {bad} out of range: the collection has {self.num_objects} objects {self.object_names}"
            )
        return ids

    def _selected(self, values: torch.Tensor, width: int, env_ids: EnvIds, object_ids: ObjectIds, what: str):
        """(the object's ``(envs, width)`` values, object) for each selected object. ``values`` is
        ``(envs, objects, width)`` or broadcasts to it, as Isaac Lab's writers take (e.g. one env's
        ``(objects, width)``)."""
        ids = self._object_list(object_ids)
        if env_ids is None or is_mask(env_ids):
            n_rows = self.num_instances  # a mask selects rows of values given for every env
        elif isinstance(env_ids, slice):
            n_rows = len(range(self.num_instances)[env_ids])
        else:
            n_rows = len(env_ids)
        shape = (n_rows, len(ids), width)
        try:
            fits = values.ndim <= 3 and torch.broadcast_shapes(values.shape, shape) == shape
        except RuntimeError:
            fits = False
        if not fits:
            raise ValueError(
                f"{what} must have shape ({n_rows}, {len(ids)}, {width}) (envs, objects, {width}) for the selection,"
                f" or one that broadcasts to it; got {tuple(values.shape)}"
            )
        values = values.expand(shape)
        return [(values[:, column], self._objects[i]) for column, i in enumerate(ids)]
