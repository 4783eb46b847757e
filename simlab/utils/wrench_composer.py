"""Isaac Lab's wrench composer: the external forces and torques of an asset's bodies, summed per body.

Every asset with bodies has two (``asset.permanent_wrench_composer``, applied every physics step
until changed, and ``asset.instantaneous_wrench_composer``, applied at the next step only). The
composed wrench of each body is kept in the body's link frame; wrenches given in the world frame
(``is_global=True``) are rotated into it with the body's pose at the time they are given. A force
given at ``positions`` also adds the torque of its lever arm: ``positions`` are offsets from the
link origin in the link frame, or world points when ``is_global``. The asset applies the
composed wrench at each body's centre of mass.

Inputs are torch tensors (or Warp arrays, read as torch) of shape ``(len(env_ids), len(body_ids), 3)``;
``env_ids`` may also be a ``(num_envs,)`` bool mask, as inside an env step (values then have a row per
env, and rows outside the mask are left alone).
"""

from __future__ import annotations

from typing import Any

import torch

import simlab.utils.math as math_utils
from simlab.utils.env_mask import env_mask, is_mask, rows

__all__ = ["WrenchComposer"]


def _as_torch(value: Any, device: str) -> torch.Tensor | None:
    """A tensor of ``value``: a tensor, a Warp array (``wp.to_torch``), a list or a NumPy array."""
    if value is None or isinstance(value, torch.Tensor):
        return value if value is None else value.to(device)
    if type(value).__module__.startswith("warp"):
        import warp as wp  # only when the caller already uses Warp

        return wp.to_torch(value).to(device)
    return torch.as_tensor(value, device=device)


class WrenchComposer:
    """The composed force and torque of each body of one asset, ``(num_envs, num_bodies, 3)``, link frame."""

    def __init__(self, asset: Any) -> None:
        self.num_envs = asset.num_instances
        self.num_bodies = asset.num_bodies if hasattr(asset, "num_bodies") else asset.num_objects
        self.device = str(asset.device)
        self._asset = asset
        data = asset.data
        if hasattr(data, "body_link_pos_w"):
            self._link_pose = lambda: (asset.data.body_link_pos_w, asset.data.body_link_quat_w)
        elif hasattr(data, "object_link_pos_w"):
            self._link_pose = lambda: (asset.data.object_link_pos_w, asset.data.object_link_quat_w)
        else:
            raise ValueError(
                f"WrenchComposer needs an asset whose data has body_link_pos_w/body_link_quat_w"
                f" (or object_link_*): {type(asset).__name__} has neither"
            )
        shape = (self.num_envs, self.num_bodies, 3)
        self._force_b = torch.zeros(shape, device=self.device)
        self._torque_b = torch.zeros(shape, device=self.device)
        self._active = False

    @property
    def active(self) -> bool:
        """Whether a wrench was given since the last full reset (then the asset applies it)."""
        return self._active

    @property
    def composed_force(self) -> torch.Tensor:
        """(num_envs, num_bodies, 3) summed forces, link frame."""
        return self._force_b

    @property
    def composed_torque(self) -> torch.Tensor:
        """(num_envs, num_bodies, 3) summed torques, link frame."""
        return self._torque_b

    # Isaac Lab keeps Warp arrays and offers torch views under these names; here both are torch.
    composed_force_as_torch = composed_force
    composed_torque_as_torch = composed_torque

    def add_forces_and_torques(
        self,
        forces: Any = None,
        torques: Any = None,
        positions: Any = None,
        body_ids: Any = None,
        env_ids: Any = None,
        is_global: bool = False,
    ) -> None:
        """Add wrenches to the composed ones of the selected envs and bodies."""
        self._compose(forces, torques, positions, body_ids, env_ids, is_global, add=True)

    def set_forces_and_torques(
        self,
        forces: Any = None,
        torques: Any = None,
        positions: Any = None,
        body_ids: Any = None,
        env_ids: Any = None,
        is_global: bool = False,
    ) -> None:
        """Replace the composed wrenches of the selected envs and bodies: a force or torque not
        given keeps its value; a force given at ``positions`` sets the torque to the given torque
        (zero if none) plus the force's lever-arm torque."""
        self._compose(forces, torques, positions, body_ids, env_ids, is_global, add=False)

    def reset(self, env_ids: Any = None) -> None:
        """Zero the composed wrenches of ``env_ids`` (None: every env, and the composer turns inactive)."""
        if env_ids is None:
            self._force_b.zero_()
            self._torque_b.zero_()
            self._active = False
            return
        keep = ~env_mask(_as_torch(env_ids, self.device) if not isinstance(env_ids, slice) else env_ids,
                         self.num_envs, self.device)  # fmt: skip
        self._force_b.mul_(rows(keep, self._force_b))
        self._torque_b.mul_(rows(keep, self._torque_b))

    # -- helpers ----------------------------------------------------------------------------------

    def _compose(self, forces, torques, positions, body_ids, env_ids, is_global: bool, add: bool) -> None:
        forces, torques = _as_torch(forces, self.device), _as_torch(torques, self.device)
        positions = _as_torch(positions, self.device)
        if forces is None and torques is None:
            return
        if positions is not None and forces is None:
            positions = None  # a torque is the same about any point
        env, bodies = self._env_index(env_ids), self._body_index(body_ids)
        n_env = self.num_envs if isinstance(env, slice) or is_mask(env) else len(env)
        n_body = self.num_bodies if isinstance(bodies, slice) else len(bodies)
        shape = (n_env, n_body, 3)
        forces, torques, positions = (self._check(v, shape, name) for v, name in
                                      ((forces, "forces"), (torques, "torques"), (positions, "positions")))  # fmt: skip
        if is_global or positions is not None:
            link_pos, link_quat = self._link_pose()
            link_pos, link_quat = self._select(link_pos, env, bodies), self._select(link_quat, env, bodies)
        if is_global:
            forces = None if forces is None else math_utils.quat_apply_inverse(link_quat, forces)
            torques = None if torques is None else math_utils.quat_apply_inverse(link_quat, torques)
            if positions is not None:  # world point -> offset from the link origin, link frame
                positions = math_utils.quat_apply_inverse(link_quat, positions - link_pos)
        if positions is not None:
            lever = torch.linalg.cross(positions, forces, dim=-1)
            torques = lever if torques is None else torques + lever
        if forces is not None:
            self._write(self._force_b, env, bodies, forces, add)
        if torques is not None:
            self._write(self._torque_b, env, bodies, torques, add)
        self._active = True

    def _env_index(self, env_ids: Any) -> slice | torch.Tensor:
        if env_ids is None or (isinstance(env_ids, slice) and env_ids == slice(None)):
            return slice(None)
        if isinstance(env_ids, slice):
            raise ValueError(f"env_ids may be None, slice(None), ids or a bool mask; got the slice {env_ids}")
        ids = _as_torch(env_ids, self.device)
        return ids if ids.dtype == torch.bool else ids.long().flatten()

    def _body_index(self, body_ids: Any) -> slice | torch.Tensor:
        if body_ids is None or (isinstance(body_ids, slice) and body_ids == slice(None)):
            return slice(None)
        if isinstance(body_ids, slice):
            raise ValueError(f"body_ids may be None, slice(None) or ids; got the slice {body_ids}")
        return _as_torch(body_ids, self.device).long().flatten()

    @staticmethod
    def _check(value: torch.Tensor | None, shape: tuple[int, int, int], name: str) -> torch.Tensor | None:
        if value is None:
            return None
        if value.shape != shape:
            got = tuple(value.shape)
            raise ValueError(f"{name} must have shape {shape} (envs, bodies, 3) for the selection, got {got}")
        return value.to(torch.float32)

    @staticmethod
    def _select(values: torch.Tensor, env, bodies) -> torch.Tensor:
        picked = values if isinstance(env, slice) or is_mask(env) else values[env]
        return picked[:, bodies]

    @staticmethod
    def _write(dst: torch.Tensor, env, bodies, values: torch.Tensor, add: bool) -> None:
        if is_mask(env):  # values for every env: keep the rows outside the mask
            old = dst[:, bodies]
            new = old + values if add else values
            dst[:, bodies] = torch.where(rows(env, old), new, old)
        elif isinstance(env, slice):
            dst[:, bodies] = dst[:, bodies] + values if add else values
        elif isinstance(bodies, slice):
            dst[env] = dst[env] + values if add else values
        else:
            index = (env[:, None], bodies[None, :])
            dst[index] = dst[index] + values if add else values
