"""The mass properties of an asset's bodies under PhysX's view names (``asset.root_physx_view``).

Isaac Lab's task files read and randomize masses through PhysX's tensor views:
``robot.root_physx_view.get_masses()`` (the quadcopter weighs itself this way) and
``set_masses(masses, env_ids)``. As PhysX does, these return and take CPU tensors with a row per env
and a column per body (the asset's body order); they read and write MuJoCo's per-world
``body_mass`` / ``body_inertia`` fields. ``get_link_incoming_joint_force()`` (the in-hand tasks'
fingertip wrenches) is ``data.body_incoming_joint_wrench_b``, on the sim's device as PhysX's GPU view
gives it. The rest of PhysX's view has no counterpart: asking for it is an error that says where the
state is.
"""

from __future__ import annotations

import contextlib
from typing import Any

import torch

import simlab.utils.math as math_utils


class BodyPropertiesView:
    """Masses and inertias of one asset's bodies in every world, PhysX's shapes, on the CPU."""

    def __init__(self, asset: Any):
        self._asset = asset
        self.count = asset.num_instances

    def get_masses(self) -> torch.Tensor:
        """(num_envs, num_bodies) masses in kg."""
        return self._field("body_mass").cpu().clone()

    def set_masses(self, masses: torch.Tensor, indices: torch.Tensor | list[int]) -> None:
        """Write ``masses[indices]`` (a (num_envs, num_bodies) tensor, as ``get_masses`` gives) to those envs."""
        asset = self._asset
        env = torch.as_tensor(indices, dtype=torch.long, device=asset.device).flatten()
        values = torch.as_tensor(masses, dtype=torch.float32)
        if values.shape != (self.count, asset.num_bodies):
            raise ValueError(
                f"set_masses takes a ({self.count}, {asset.num_bodies}) tensor with a row per env, as get_masses"
                f" returns it; got {tuple(values.shape)}"
            )
        field = asset._physics.model_field("body_mass")
        env, values = env.to(field.device), values.to(field.device)
        field[env[:, None], asset._body_index.to(field.device)] = values[env]
        with contextlib.suppress(NotImplementedError):  # derived constants follow (the GPU keeps its own)
            asset._physics.set_const(env)

    def get_inertias(self) -> torch.Tensor:
        """(num_envs, num_bodies, 9) inertia tensors about each body's centre of mass, in the body
        frame, row-major (MuJoCo keeps the principal moments and the principal axes' orientation)."""
        principal = self._field("body_inertia")
        iquat = self._field("body_iquat")
        axes = math_utils.matrix_from_quat(iquat)
        tensor = axes @ torch.diag_embed(principal) @ axes.transpose(-1, -2)
        return tensor.reshape(*tensor.shape[:-2], 9).cpu()

    def get_link_incoming_joint_force(self) -> torch.Tensor:
        """PhysX's incoming joint wrenches, (count, num_bodies, 6): ``data.body_incoming_joint_wrench_b``
        (MuJoCo's post-constraint pass: compiled in by ``sim_utils.compute_body_interaction_forces``
        before the model compiles, else run by the backend when read)."""
        return self._asset.data.body_incoming_joint_wrench_b

    def _field(self, name: str) -> torch.Tensor:
        """The per-world model field if something made it per-world, else the compiled model's, repeated."""
        asset = self._asset
        physics = asset._physics
        per_world = physics.per_world_model_field(name)
        if per_world is not None:
            return per_world[:, asset._body_index.to(per_world.device)].to(torch.float32)
        model = getattr(asset._sim.model, name)[asset._body_ids]
        return torch.as_tensor(model, dtype=torch.float32).unsqueeze(0).repeat(self.count, *([1] * model.ndim))

    def __getattr__(self, name: str):
        raise AttributeError(
            f"simlab's root_physx_view has no '{name}': it offers get_masses, set_masses and get_inertias"
            " (articulations also get_dof_limits, get_jacobians, get_generalized_mass_matrices, the gravity and"
            " Coriolis forces);"
            " the state is in asset.data, the model in sim.model"
        )
