"""The data of a rigid object collection (Isaac Lab's ``RigidObjectCollectionData``).

Every field is read live from the objects' own data and stacked on an object axis:
``(num_envs, num_objects, ...)``. Nothing is cached, so a field is current whenever it is read.
Isaac Lab 3.0 calls the objects bodies (``body_link_pose_w``, ``default_body_pose``, ...); both names
are here, with simlab's quaternion convention (w, x, y, z) throughout.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils

if TYPE_CHECKING:
    from ..rigid_object import RigidObject
    from .rigid_object_collection import RigidObjectCollection


class RigidObjectCollectionData:
    """Link, centre-of-mass and default states of the objects of a collection, world frame."""

    def __init__(self, collection: RigidObjectCollection, sim):
        self._collection = collection
        objects = collection._objects
        model, dev, n = sim.model, collection.device, collection.num_instances
        roots = [o._root_body for o in objects]
        # the centre of mass in each link frame: position and principal axes (the compiled model's)
        self._com_pos_b = torch.tensor(model.body_ipos[roots], dtype=torch.float32, device=dev)
        self._com_quat_b = torch.tensor(model.body_iquat[roots], dtype=torch.float32, device=dev)
        self.object_names: list[str] = list(collection.object_names)
        states = []
        for o in objects:
            init = o.cfg.init_state
            states.append([*init.pos, *init.rot, *init.lin_vel, *init.ang_vel])
        self.default_object_state = torch.tensor(states, dtype=torch.float32, device=dev).repeat(n, 1, 1)
        """(num_envs, num_objects, 13) the configs' initial states: link pose (env frame), com velocity."""
        self.default_mass = torch.tensor(model.body_mass[roots], dtype=torch.float32, device=dev)[None, :, None].repeat(
            n, 1, 1
        )
        """(num_envs, num_objects, 1) masses [kg] of the compiled model."""
        axes = math_utils.matrix_from_quat(self._com_quat_b)
        inertia = axes @ torch.diag_embed(torch.tensor(model.body_inertia[roots], dtype=torch.float32, device=dev))
        inertia = inertia @ axes.transpose(-1, -2)
        self.default_inertia = inertia.reshape(1, len(objects), 9).repeat(n, 1, 1)
        """(num_envs, num_objects, 9) inertia tensors about the centre of mass in the link frame, row-major."""
        gravity = torch.tensor(model.opt.gravity, dtype=torch.float32, device=dev)
        norm = torch.linalg.norm(gravity)
        gravity = gravity / norm if norm > 0 else torch.tensor([0.0, 0.0, -1.0], device=dev)
        self.GRAVITY_VEC_W = gravity.repeat(n, len(objects), 1)
        self.FORWARD_VEC_B = torch.tensor([1.0, 0.0, 0.0], device=dev).repeat(n, len(objects), 1)

    def _stack(self, field: str) -> torch.Tensor:
        return torch.stack([getattr(o.data, field) for o in self._collection._objects], dim=1)

    def _com_offset(self, rigid_object: RigidObject) -> tuple[torch.Tensor, torch.Tensor]:
        """(3,) position and (4,) orientation of ``rigid_object``'s centre-of-mass frame in its link frame."""
        k = self._collection._objects.index(rigid_object)
        return self._com_pos_b[k], self._com_quat_b[k]

    # -- link frame -------------------------------------------------------------------------------

    @property
    def object_link_pos_w(self) -> torch.Tensor:
        return self._stack("root_pos_w")

    @property
    def object_link_quat_w(self) -> torch.Tensor:
        return self._stack("root_quat_w")

    @property
    def object_link_pose_w(self) -> torch.Tensor:
        return torch.cat([self.object_link_pos_w, self.object_link_quat_w], dim=-1)

    @property
    def object_link_lin_vel_w(self) -> torch.Tensor:
        return self._stack("root_lin_vel_w")

    @property
    def object_link_ang_vel_w(self) -> torch.Tensor:
        return self._stack("root_ang_vel_w")

    @property
    def object_link_vel_w(self) -> torch.Tensor:
        return torch.cat([self.object_link_lin_vel_w, self.object_link_ang_vel_w], dim=-1)

    @property
    def object_link_state_w(self) -> torch.Tensor:
        return torch.cat([self.object_link_pose_w, self.object_link_vel_w], dim=-1)

    @property
    def object_link_lin_vel_b(self) -> torch.Tensor:
        return math_utils.quat_apply_inverse(self.object_link_quat_w, self.object_link_lin_vel_w)

    @property
    def object_link_ang_vel_b(self) -> torch.Tensor:
        return math_utils.quat_apply_inverse(self.object_link_quat_w, self.object_link_ang_vel_w)

    # -- centre-of-mass frame ---------------------------------------------------------------------

    @property
    def object_com_pos_b(self) -> torch.Tensor:
        """(num_envs, num_objects, 3) centre of mass in the link frame."""
        return self._com_pos_b.expand(self._collection.num_instances, -1, -1)

    @property
    def object_com_quat_b(self) -> torch.Tensor:
        """(num_envs, num_objects, 4) principal axes of inertia in the link frame."""
        return self._com_quat_b.expand(self._collection.num_instances, -1, -1)

    @property
    def object_com_pos_w(self) -> torch.Tensor:
        return self.object_link_pos_w + math_utils.quat_apply(self.object_link_quat_w, self.object_com_pos_b)

    @property
    def object_com_quat_w(self) -> torch.Tensor:
        return math_utils.quat_mul(self.object_link_quat_w, self.object_com_quat_b)

    @property
    def object_com_pose_w(self) -> torch.Tensor:
        return torch.cat([self.object_com_pos_w, self.object_com_quat_w], dim=-1)

    @property
    def object_com_lin_vel_w(self) -> torch.Tensor:
        """Velocity of the centre of mass: the link origin's plus w x (com - link origin)."""
        lever = math_utils.quat_apply(self.object_link_quat_w, self.object_com_pos_b)
        return self.object_link_lin_vel_w + torch.linalg.cross(self.object_link_ang_vel_w, lever, dim=-1)

    @property
    def object_com_ang_vel_w(self) -> torch.Tensor:
        return self.object_link_ang_vel_w

    @property
    def object_com_vel_w(self) -> torch.Tensor:
        return torch.cat([self.object_com_lin_vel_w, self.object_com_ang_vel_w], dim=-1)

    @property
    def object_com_state_w(self) -> torch.Tensor:
        return torch.cat([self.object_com_pose_w, self.object_com_vel_w], dim=-1)

    @property
    def object_com_lin_vel_b(self) -> torch.Tensor:
        return math_utils.quat_apply_inverse(self.object_link_quat_w, self.object_com_lin_vel_w)

    @property
    def object_com_ang_vel_b(self) -> torch.Tensor:
        return math_utils.quat_apply_inverse(self.object_link_quat_w, self.object_com_ang_vel_w)

    # -- Isaac Lab's mixed state: link pose, com velocity -----------------------------------------

    object_pos_w = object_link_pos_w
    object_quat_w = object_link_quat_w
    object_pose_w = object_link_pose_w
    object_lin_vel_w = object_com_lin_vel_w
    object_ang_vel_w = object_com_ang_vel_w
    object_vel_w = object_com_vel_w
    object_lin_vel_b = object_com_lin_vel_b
    object_ang_vel_b = object_com_ang_vel_b

    @property
    def object_state_w(self) -> torch.Tensor:
        """(num_envs, num_objects, 13): link pose (pos, quat w-x-y-z) and com velocity (lin, ang)."""
        return torch.cat([self.object_link_pose_w, self.object_com_vel_w], dim=-1)

    @property
    def projected_gravity_b(self) -> torch.Tensor:
        return math_utils.quat_apply_inverse(self.object_link_quat_w, self.GRAVITY_VEC_W)

    @property
    def heading_w(self) -> torch.Tensor:
        forward = math_utils.quat_apply(self.object_link_quat_w, self.FORWARD_VEC_B)
        return torch.atan2(forward[..., 1], forward[..., 0])

    # -- Isaac Lab 3.0's names: the objects are the collection's bodies ---------------------------

    body_link_pos_w = object_link_pos_w
    body_link_quat_w = object_link_quat_w
    body_link_pose_w = object_link_pose_w
    body_link_lin_vel_w = object_link_lin_vel_w
    body_link_ang_vel_w = object_link_ang_vel_w
    body_link_vel_w = object_link_vel_w
    body_link_state_w = object_link_state_w
    body_link_lin_vel_b = object_link_lin_vel_b
    body_link_ang_vel_b = object_link_ang_vel_b
    body_com_pos_w = object_com_pos_w
    body_com_quat_w = object_com_quat_w
    body_com_pose_w = object_com_pose_w
    body_com_lin_vel_w = object_com_lin_vel_w
    body_com_ang_vel_w = object_com_ang_vel_w
    body_com_vel_w = object_com_vel_w
    body_com_state_w = object_com_state_w
    body_com_lin_vel_b = object_com_lin_vel_b
    body_com_ang_vel_b = object_com_ang_vel_b
    body_com_pos_b = com_pos_b = object_com_pos_b
    body_com_quat_b = com_quat_b = object_com_quat_b
    body_pos_w = object_pos_w
    body_quat_w = object_quat_w
    body_pose_w = object_pose_w
    body_lin_vel_w = object_lin_vel_w
    body_ang_vel_w = object_ang_vel_w
    body_vel_w = object_vel_w
    body_state_w = object_state_w

    @property
    def default_body_pose(self) -> torch.Tensor:
        """(num_envs, num_objects, 7) the configs' initial link poses, env frame."""
        return self.default_object_state[..., :7]

    @property
    def default_body_vel(self) -> torch.Tensor:
        """(num_envs, num_objects, 6) the configs' initial com velocities."""
        return self.default_object_state[..., 7:]

    default_object_pose = default_body_pose
    default_object_vel = default_body_vel
    default_body_state = property(lambda self: self.default_object_state)

    @property
    def body_mass(self) -> torch.Tensor:
        """(num_envs, num_objects) masses [kg] of each world's model."""
        return torch.stack([o.data.body_mass[:, 0] for o in self._collection._objects], dim=1)

    @property
    def body_names(self) -> list[str]:
        return self.object_names
