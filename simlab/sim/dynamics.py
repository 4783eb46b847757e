"""Jacobians, mass matrices and gravity forces of a kinematic tree, batched over worlds.

Computed in torch from the quantities MuJoCo's forward pass leaves in MjData, so one code path
serves both backends (MuJoCo C through mjbatch, MuJoCo Warp) and a captured env step:

* ``cdof`` (nv, 6): each dof's motion axis ``[angular, linear]`` in the frame centred on its
  tree's centre of mass (``subtree_com`` of the tree's root); MuJoCo's ``mj_jac`` builds the
  Jacobian of a point ``p`` on body ``b`` from it: for every dof ``j`` that moves ``b``,
  ``jac_rot[:, j] = cdof[j, :3]`` and ``jac_pos[:, j] = cdof[j, 3:] + cdof[j, :3] x (p - com)``.
* The joint-space mass matrix is then ``sum_b m_b Jp_b^T Jp_b + Jr_b^T I_b Jr_b`` over the tree's
  bodies (``Jp`` at each body's centre of mass, ``I_b`` its inertia in the world frame) plus the
  dofs' armature: the matrix ``mj_fullM`` gives.

Masses, inertias and armatures are read per world (``PhysicsBackend.model_field``), so
randomized masses are seen.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np
import torch


class TreeDynamics:
    """Jacobians of ``body_ids`` over the dofs ``dof_ids``, and the dynamics over those dofs.

    Args:
        physics: the simulation's backend.
        model: the compiled model.
        body_ids: model body ids whose Jacobians are wanted (their order is kept).
        dof_ids: model dof ids giving the Jacobian columns (their order is kept).
    """

    def __init__(self, physics, model: mujoco.MjModel, body_ids: Sequence[int], dof_ids: Sequence[int]):
        self._physics = physics
        dev = physics.device
        self.body_ids = list(body_ids)
        self.dof_ids = list(dof_ids)
        self._body_index = torch.tensor(self.body_ids, dtype=torch.long, device=dev)
        self._dof_index = torch.tensor(self.dof_ids, dtype=torch.long, device=dev)
        self._root_of_body = torch.tensor(model.body_rootid[self.body_ids], dtype=torch.long, device=dev)
        self._moves = torch.tensor(_dof_moves_body(model, self.body_ids, self.dof_ids), device=dev)

        # Bodies whose motion the selected dofs produce: the terms of the mass matrix.
        moved = [b for b in range(1, model.nbody) if _dof_moves_body(model, [b], self.dof_ids).any()]
        self._mass_bodies = torch.tensor(moved, dtype=torch.long, device=dev)
        self._mass_root = torch.tensor(model.body_rootid[moved], dtype=torch.long, device=dev)
        self._mass_moves = torch.tensor(_dof_moves_body(model, moved, self.dof_ids), device=dev)
        self._gravcomp_model = torch.tensor(model.body_gravcomp, dtype=torch.float32, device=dev)
        self._gravity_model = torch.tensor(model.opt.gravity, dtype=torch.float32, device=dev)

        self._cdof = physics.data("cdof")
        self._subtree_com = physics.data("subtree_com")
        self._xpos = physics.data("xpos")
        self._xipos = physics.data("xipos")
        self._ximat = physics.data("ximat")
        self._qfrc_bias = physics.data("qfrc_bias")
        self._mass = physics.model_field("body_mass")
        self._inertia = physics.model_field("body_inertia")
        self._armature = physics.model_field("dof_armature")

    # -- Jacobians -----------------------------------------------------------------------------

    def jacobians(self, points_w: torch.Tensor | None = None) -> torch.Tensor:
        """(num_envs, num_bodies, 6, num_dofs): rows ``[linear; angular]`` velocity, world frame.

        The linear rows are the velocity of ``points_w`` (num_envs, num_bodies, 3) — positions in the
        simulation's per-world frame — or of each body's frame origin when None.
        """
        self._physics.ensure_forward()
        if points_w is None:
            points_w = self._xpos[:, self._body_index]
        com = self._subtree_com[:, self._root_of_body]
        return _point_jacobians(self._cdof[:, self._dof_index], points_w - com, self._moves)

    # -- dynamics ------------------------------------------------------------------------------

    def mass_matrix(self) -> torch.Tensor:
        """(num_envs, num_dofs, num_dofs) joint-space mass matrix (MuJoCo's, armature included)."""
        self._physics.ensure_forward()
        bodies = self._mass_bodies
        jac = _point_jacobians(
            self._cdof[:, self._dof_index],
            self._xipos[:, bodies] - self._subtree_com[:, self._mass_root],
            self._mass_moves,
        )
        jac_pos, jac_rot = jac[:, :, :3], jac[:, :, 3:]
        mass = self._mass[:, bodies]
        rot = self._ximat[:, bodies].reshape(-1, len(bodies), 3, 3)
        inertia_w = rot @ torch.diag_embed(self._inertia[:, bodies]) @ rot.transpose(-1, -2)
        m_lin = torch.einsum("nb,nbid,nbie->nde", mass, jac_pos, jac_pos)
        m_rot = torch.einsum("nbid,nbij,nbje->nde", jac_rot, inertia_w, jac_rot)
        return m_lin + m_rot + torch.diag_embed(self._armature[:, self._dof_index])

    def gravity_forces(self, honour_gravcomp: bool = True) -> torch.Tensor:
        """(num_envs, num_dofs) generalized forces that hold the tree against gravity.

        With ``honour_gravcomp``, bodies whose gravity the model compensates (``gravcomp``, what
        ``disable_gravity`` sets) contribute nothing, as a gravity-free body in PhysX.
        """
        self._physics.ensure_forward()
        bodies = self._mass_bodies
        jac = _point_jacobians(
            self._cdof[:, self._dof_index],
            self._xipos[:, bodies] - self._subtree_com[:, self._mass_root],
            self._mass_moves,
        )
        weight = self._mass[:, bodies]
        if honour_gravcomp:
            weight = weight * (1.0 - self._gravcomp_model[bodies])
        force = -weight[..., None] * self._gravity_model  # (N, B, 3): the force that cancels gravity
        return torch.einsum("nbid,nbi->nd", jac[:, :, :3], force)

    def coriolis_and_centrifugal_forces(self) -> torch.Tensor:
        """(num_envs, num_dofs) velocity-product forces ``C(q, qd) qd`` (MuJoCo's bias minus gravity)."""
        self._physics.ensure_forward()
        return self._qfrc_bias[:, self._dof_index] - self.gravity_forces(honour_gravcomp=False)


def _point_jacobians(cdof: torch.Tensor, offset: torch.Tensor, moves: torch.Tensor) -> torch.Tensor:
    """(N, B, 6, D) Jacobians of points at ``offset`` (N, B, 3) from their tree's centre of mass."""
    ang, lin = cdof[..., :3], cdof[..., 3:]  # (N, D, 3)
    jac_pos = lin[:, None] + torch.cross(ang[:, None].expand(-1, offset.shape[1], -1, -1), offset[:, :, None], dim=-1)
    jac_rot = ang[:, None].expand_as(jac_pos)
    jac = torch.cat([jac_pos, jac_rot], dim=-1) * moves[None, :, :, None]  # (N, B, D, 6)
    return jac.transpose(-1, -2)


def _dof_moves_body(model: mujoco.MjModel, body_ids: Sequence[int], dof_ids: Sequence[int]) -> np.ndarray:
    """(B, D) float: 1 where dof ``d`` moves body ``b`` (its joint's body is ``b`` or an ancestor)."""
    out = np.zeros((len(body_ids), len(dof_ids)), dtype=np.float32)
    for i, body in enumerate(body_ids):
        chain = set()
        b = body
        while b > 0:
            chain.add(b)
            b = int(model.body_parentid[b])
        for k, dof in enumerate(dof_ids):
            out[i, k] = float(int(model.dof_bodyid[dof]) in chain)
    return out
