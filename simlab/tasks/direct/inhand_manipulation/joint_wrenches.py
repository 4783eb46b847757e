"""The wrench each chosen body receives through its joint from its parent, read from MuJoCo force and
torque sensors: what Isaac Lab reads from PhysX as ``get_link_incoming_joint_force()`` for the
fingertip force-torque observations of the asymmetric critic.

A MuJoCo ``force`` / ``torque`` sensor on a site reports the interaction between the site's body and
its parent, in the site's frame; a site at each body's origin makes it the incoming joint wrench in
the body frame. The sensors put MuJoCo's post-constraint pass (``mj_rnePostConstraint``) into every
step, so a task adds them only when it reads them.
"""

from __future__ import annotations

import mujoco
import torch

from simlab.sim import SimulationContext


class IncomingJointWrenches:
    """``read()`` -> (num_envs, len(body_names), 6): force then torque, in each body's frame.

    Create it before the model compiles (in a direct env's ``_setup_scene``, after the articulation).
    """

    def __init__(self, sim: SimulationContext, prefix: str, body_names: list[str]):
        self._sim = sim
        self._sites = [f"{prefix}{name}/incoming_wrench" for name in body_names]
        spec = sim.spec
        for name, site in zip(body_names, self._sites):
            body = spec.body(prefix + name)
            if body is None:
                raise ValueError(f"IncomingJointWrenches: the model has no body '{prefix}{name}'")
            body.add_site(name=site, group=5)
            for kind in ("force", "torque"):
                sensor_type = mujoco.mjtSensor.mjSENS_FORCE if kind == "force" else mujoco.mjtSensor.mjSENS_TORQUE
                spec.add_sensor(name=f"{site}/{kind}", type=sensor_type, objtype=mujoco.mjtObj.mjOBJ_SITE, objname=site)
        sim.add_reset_callback(self._bind)

    def _bind(self, sim: SimulationContext) -> None:
        model = sim.model
        cols = [
            int(model.sensor(f"{site}/{kind}").adr[0]) + i
            for site in self._sites
            for kind in ("force", "torque")
            for i in range(3)
        ]
        self._cols = torch.tensor(cols, dtype=torch.long, device=sim.device)
        self._sensordata = sim.physics.data("sensordata")

    def read(self) -> torch.Tensor:
        self._sim.physics.ensure_forward()
        return self._sensordata[:, self._cols].view(-1, len(self._sites), 6)
