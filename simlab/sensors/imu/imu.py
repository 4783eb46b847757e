"""The IMU: pose, velocities and accelerations of a point on a body, in that point's frame.

A site at ``offset`` on the body carries four MuJoCo sensors (velocimeter, gyro, frame linear and
angular acceleration), which both MuJoCo and MuJoCo Warp compute at every forward from the
model's own dynamics (exact accelerations, not finite differences of velocities as Isaac Lab's).
``lin_acc_b`` is the true acceleration plus ``gravity_bias``: at rest it reads +9.81 up, in free
fall zero.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

import mujoco
import torch

from simlab.utils.env_mask import EnvIds
from simlab.utils.math import quat_apply_inverse, quat_from_matrix

from ..sensor_base import SensorBase, prim_path_in_model

if TYPE_CHECKING:
    from .imu_cfg import ImuCfg

_READINGS = {
    "lin_vel": mujoco.mjtSensor.mjSENS_VELOCIMETER,
    "ang_vel": mujoco.mjtSensor.mjSENS_GYRO,
    "lin_acc": mujoco.mjtSensor.mjSENS_FRAMELINACC,
    "ang_acc": mujoco.mjtSensor.mjSENS_FRAMEANGACC,
}


class ImuData:
    """Shapes use N envs."""

    def __init__(self):
        self.pos_w: torch.Tensor | None = None
        """(N, 3) position of the IMU, world frame."""
        self.quat_w: torch.Tensor | None = None
        """(N, 4) orientation (w, x, y, z) of the IMU, world frame."""
        self.projected_gravity_b: torch.Tensor | None = None
        """(N, 3) unit gravity direction in the IMU frame."""
        self.lin_vel_b: torch.Tensor | None = None
        """(N, 3) linear velocity of the IMU point, IMU frame [m/s]."""
        self.ang_vel_b: torch.Tensor | None = None
        """(N, 3) angular velocity, IMU frame [rad/s]."""
        self.lin_acc_b: torch.Tensor | None = None
        """(N, 3) linear acceleration of the IMU point plus ``gravity_bias``, IMU frame [m/s^2]."""
        self.ang_acc_b: torch.Tensor | None = None
        """(N, 3) angular acceleration, IMU frame [rad/s^2]."""


class Imu(SensorBase):
    cfg: ImuCfg

    def __init__(self, cfg: ImuCfg, scene=None):
        super().__init__(cfg, scene)
        self._owner = f"ImuCfg('{cfg.prim_path}')"
        self._site = f"simlab/imu/{prim_path_in_model(cfg.prim_path)}"
        self._data = ImuData()
        self._timestamp = 0.0
        self._outdated = True
        self._sim.add_build_callback(self._add_to_spec)

    def __str__(self) -> str:
        return f"Imu @ '{self.cfg.prim_path}'"

    @property
    def data(self) -> ImuData:
        """The readings, computed now if the state changed (an update was due) or envs were reset
        since they were last computed."""
        if self._outdated and self._is_initialized:
            self._read()
        return self._data

    def reset(self, env_ids: EnvIds = None) -> None:
        """Nothing is kept between readings; the next read computes them from the new state."""
        self._outdated = True

    def update(self, dt: float, force_recompute: bool = False) -> None:
        """Called by the scene every physics step: marks the readings outdated every
        ``update_period``; they are computed when read (Isaac Lab's lazy update)."""
        if not self._is_initialized:
            return
        self._timestamp += dt
        if self.cfg.update_period > 0.0 and self._timestamp + 1e-9 < self.cfg.update_period and not force_recompute:
            return
        self._timestamp = 0.0
        self._outdated = True
        if force_recompute:
            self._read()

    def _read(self) -> None:
        self._outdated = False
        self._sim.physics.ensure_forward()
        d, n = self._data, self.num_instances
        quat_w = quat_from_matrix(self._site_xmat[:, self._site_id].view(n, 3, 3))
        d.pos_w.copy_(self._site_xpos[:, self._site_id] + self._sim.env_origins)
        d.quat_w.copy_(quat_w)
        d.lin_vel_b.copy_(self._reading("lin_vel"))
        d.ang_vel_b.copy_(self._reading("ang_vel"))
        d.lin_acc_b.copy_(quat_apply_inverse(quat_w, self._reading("lin_acc") + self._acc_offset))
        d.ang_acc_b.copy_(quat_apply_inverse(quat_w, self._reading("ang_acc")))
        d.projected_gravity_b.copy_(quat_apply_inverse(quat_w, self._gravity_dir.expand(n, 3)))

    # -- building -------------------------------------------------------------------------------

    def _add_to_spec(self, spec: mujoco.MjSpec) -> None:
        """A site at the offset on the body, with the four sensors on it (before compiling)."""
        path = prim_path_in_model(self.cfg.prim_path)
        if "/" in path:
            bodies = [b for b in spec.bodies if b.name and re.fullmatch(path, b.name)]
        else:  # the asset itself: its root body
            bodies = [b for b in spec.worldbody.bodies if b.name.startswith(path + "/")]
        if len(bodies) != 1:
            names = [b.name for b in spec.bodies if b.name and b.name != "world"]
            found = "matches no body" if not bodies else f"matches {len(bodies)} bodies {[b.name for b in bodies]}"
            raise ValueError(
                f"{self._owner} prim_path {found}; it must name one body, e.g. '{{ENV_REGEX_NS}}/Robot/base'."
                f" Bodies in the model: {names}"
            )
        if spec.site(self._site) is not None:
            raise ValueError(f"{self._owner}: two IMUs on the same body; give each sensor its own body")
        bodies[0].add_site(name=self._site, pos=list(self.cfg.offset.pos), quat=list(self.cfg.offset.rot), group=5)
        for reading, sensor_type in _READINGS.items():
            spec.add_sensor(
                name=f"{self._site}/{reading}", type=sensor_type, objtype=mujoco.mjtObj.mjOBJ_SITE, objname=self._site
            )

    def _initialize(self, sim) -> None:
        model, physics, n, dev = sim.model, sim.physics, self.num_instances, self.device
        self._site_id = model.site(self._site).id
        self._adr = {r: int(model.sensor(f"{self._site}/{r}").adr[0]) for r in _READINGS}
        self._sensordata = physics.data("sensordata")
        self._site_xpos, self._site_xmat = physics.data("site_xpos"), physics.data("site_xmat")
        gravity = torch.tensor(model.opt.gravity, dtype=torch.float32, device=dev)
        # MuJoCo's frame accelerations carry -gravity (its world body accelerates up by -g in the
        # recursion): adding gravity gives the true acceleration, then the bias is added
        self._acc_offset = gravity + torch.tensor(self.cfg.gravity_bias, dtype=torch.float32, device=dev)
        norm = float(gravity.norm())
        self._gravity_dir = gravity / norm if norm > 0 else torch.tensor([0.0, 0.0, -1.0], device=dev)
        d = self._data
        for name in ("pos_w", "projected_gravity_b", "lin_vel_b", "ang_vel_b", "lin_acc_b", "ang_acc_b"):
            setattr(d, name, torch.zeros(n, 3, device=dev))
        d.quat_w = torch.zeros(n, 4, device=dev)
        super()._initialize(sim)

    def _reading(self, name: str) -> torch.Tensor:
        adr = self._adr[name]
        return self._sensordata[:, adr : adr + 3]
