"""The wrench each chosen body receives through its joint from its parent, read from MuJoCo force and
torque sensors: what Isaac Lab reads from PhysX as ``get_link_incoming_joint_force()`` for the
fingertip force-torque observations of the asymmetric critic.

A MuJoCo ``force`` / ``torque`` sensor on a site reports the interaction between the site's body and
its parent, in the site's frame; a site at each body's origin makes it the incoming joint wrench in
the body frame. The sensors put MuJoCo's post-constraint pass (``mj_rnePostConstraint``) into every
step, so a task adds them only when it reads them.

Isaac Lab's ``disable_gravity`` is MuJoCo's gravity compensation here, a joint-space force the
sensors do not see: they would report the weight of a body that PhysX treats as weightless. The
compensating force on the body and its descendants (at their centres of mass) is taken out, so a
fingertip at rest reads zero, as in PhysX.
"""

from __future__ import annotations

import mujoco
import torch

from simlab.sim import SimulationContext
from simlab.utils.math import quat_apply_inverse, quat_from_matrix


class IncomingJointWrenches:
    """``read()`` -> (num_envs, len(body_names), 6): force then torque, in each body's frame.

    Create it before the model compiles (in a direct env's ``_setup_scene``, after the articulation).
    """

    def __init__(self, sim: SimulationContext, prefix: str, body_names: list[str]):
        self._sim = sim
        self._bodies = [prefix + name for name in body_names]
        self._sites = [f"{body}/incoming_wrench" for body in self._bodies]
        spec = sim.spec
        for body_name, site in zip(self._bodies, self._sites):
            body = spec.body(body_name)
            if body is None:
                raise ValueError(f"IncomingJointWrenches: the model has no body '{body_name}'")
            body.add_site(name=site, group=5)
            for kind, sensor_type in (
                ("force", mujoco.mjtSensor.mjSENS_FORCE),
                ("torque", mujoco.mjtSensor.mjSENS_TORQUE),
            ):
                spec.add_sensor(name=f"{site}/{kind}", type=sensor_type, objtype=mujoco.mjtObj.mjOBJ_SITE, objname=site)
        sim.add_reset_callback(self._bind)

    def _bind(self, sim: SimulationContext) -> None:
        model, dev = sim.model, sim.device
        cols = [
            int(model.sensor(f"{site}/{kind}").adr[0]) + i
            for site in self._sites
            for kind in ("force", "torque")
            for i in range(3)
        ]
        self._cols = torch.tensor(cols, dtype=torch.long, device=dev)
        self._site_ids = torch.tensor([model.site(s).id for s in self._sites], dtype=torch.long, device=dev)
        # gravity-compensated bodies under each tracked body (itself included): (tracked, nbody) weights
        owner = torch.zeros(len(self._bodies), model.nbody, device=dev)
        for row, name in enumerate(self._bodies):
            root = model.body(name).id
            for b in range(model.nbody):
                a = b
                while a > 0 and a != root:
                    a = int(model.body_parentid[a])
                if a == root:
                    owner[row, b] = float(model.body_gravcomp[b])
        self._gravcomp = owner
        self._any_gravcomp = bool(owner.any())  # known once: the step reads nothing back from the device
        self._mass = torch.tensor(model.body_mass, dtype=torch.float32, device=dev)
        self._gravity = torch.tensor(model.opt.gravity, dtype=torch.float32, device=dev)
        physics = sim.physics
        self._physics = physics
        self._sensordata = physics.data("sensordata")
        self._xipos = physics.data("xipos")
        self._site_xpos, self._site_xmat = physics.data("site_xpos"), physics.data("site_xmat")

    def read(self) -> torch.Tensor:
        self._sim.physics.ensure_forward()
        n, k = self._sensordata.shape[0], len(self._sites)
        wrench = self._sensordata[:, self._cols].view(n, k, 6)
        if not self._any_gravcomp:
            return wrench
        mass = self._physics.per_world_model_field("body_mass")
        gravity = self._physics.per_world_model_field("opt.gravity")
        mass = self._mass.expand(n, -1) if mass is None else mass
        gravity = self._gravity.expand(n, 3) if gravity is None else gravity
        # compensating force on each body (world frame): -gravcomp * m * g at its centre of mass
        weights = self._gravcomp[None] * mass[:, None, :]  # (n, k, nbody)
        body_force = -weights[..., None] * gravity[:, None, None, :]  # (n, k, nbody, 3)
        site_pos = self._site_xpos[:, self._site_ids]  # (n, k, 3)
        lever = self._xipos[:, None, :, :] - site_pos[:, :, None, :]
        force_w = body_force.sum(dim=2)
        torque_w = torch.linalg.cross(lever, body_force, dim=-1).sum(dim=2)
        quat = quat_from_matrix(self._site_xmat[:, self._site_ids].view(n, k, 3, 3))
        correction = torch.cat((quat_apply_inverse(quat, force_w), quat_apply_inverse(quat, torque_w)), dim=-1)
        return wrench - correction
