"""Contact sensors: net contact force on each selected body, its history, and air/contact times.

MuJoCo computes the external wrench on every body (``cfrc_ext``: contacts, equality constraints
and applied forces, as ``[torque, force]`` in the world frame) in ``mj_rnePostConstraint``, which
the forward pass runs only when the model has an acceleration-stage sensor. The sensor therefore
adds one accelerometer on a world site to the model (both MuJoCo C and MuJoCo Warp then fill
``cfrc_ext`` at every step) and reads the force part, minus the forces applied through
``xfrc_applied``, so that what remains is the contact force on the body (equality-constraint
forces, where a model has them, are included).

The forces read are those of the physics step just taken: ``mj_step`` computes them from the state
it starts from and they drive it to the next state (what PhysX reports for its step too), so the
sensor needs no extra forward pass per physics step (one per substep would cost about half a step
more). The scene updates the sensor right after each physics step, before anything recomputes
derived quantities.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import torch

from simlab.utils import configclass
from simlab.utils.env_mask import env_mask, masked_copy_
from simlab.utils.string import resolve_matching_names

from .sensor_base import SensorBase, SensorBaseCfg, find_sensor_bodies

_TRIGGER_SITE = "simlab/contact_forces"


class ContactSensorData:
    """Buffers of a contact sensor; shapes use N envs, B bodies, T history steps."""

    def __init__(self):
        self.net_forces_w: torch.Tensor | None = None
        """(N, B, 3) net contact force on each body, world frame."""
        self.net_forces_w_history: torch.Tensor | None = None
        """(N, T, B, 3) the last T values of ``net_forces_w``, newest first (T >= 1)."""
        self.pos_w: torch.Tensor | None = None
        """(N, B, 3) body positions (with ``track_pose``)."""
        self.quat_w: torch.Tensor | None = None
        self.current_air_time: torch.Tensor | None = None
        """(N, B) seconds since the body last touched (with ``track_air_time``)."""
        self.last_air_time: torch.Tensor | None = None
        """(N, B) length of the last flight phase."""
        self.current_contact_time: torch.Tensor | None = None
        self.last_contact_time: torch.Tensor | None = None
        self.force_matrix_w: torch.Tensor | None = None


class ContactSensor(SensorBase):
    """Net contact forces of the bodies matched by ``prim_path`` (``{ENV_REGEX_NS}/Robot/.*``)."""

    cfg: ContactSensorCfg

    def __init__(self, cfg: ContactSensorCfg, scene=None):
        super().__init__(cfg, scene)
        if cfg.filter_prim_paths_expr:
            raise ValueError(
                "ContactSensorCfg.filter_prim_paths_expr (per-partner force matrix) is not supported by simlab;"
                " leave it empty"
            )
        # An acceleration-stage sensor makes MuJoCo's forward pass compute cfrc_ext.
        spec = self._sim.spec
        if spec.site(_TRIGGER_SITE) is None:
            spec.worldbody.add_site(name=_TRIGGER_SITE, group=5)
            spec.add_sensor(
                name=_TRIGGER_SITE,
                type=mujoco.mjtSensor.mjSENS_ACCELEROMETER,
                objtype=mujoco.mjtObj.mjOBJ_SITE,
                objname=_TRIGGER_SITE,
            )
        self._data = ContactSensorData()
        self._timestamp = 0.0

    def __str__(self) -> str:
        return f"ContactSensor @ '{self.cfg.prim_path}': {self.num_bodies} bodies {self.body_names}"

    # -- Isaac Lab's API ------------------------------------------------------------------------

    @property
    def data(self) -> ContactSensorData:
        return self._data

    @property
    def num_bodies(self) -> int:
        return len(self._body_names)

    @property
    def body_names(self) -> list[str]:
        return self._body_names

    def find_bodies(self, name_keys: str | Sequence[str], preserve_order: bool = False) -> tuple[list[int], list[str]]:
        return resolve_matching_names(name_keys, self._body_names, preserve_order)

    def compute_first_contact(self, dt: float, abs_tol: float = 1.0e-8) -> torch.Tensor:
        """(N, B) bodies that touched within the last ``dt`` seconds after a flight."""
        self._need_air_time("compute_first_contact")
        in_contact = self._data.current_contact_time > 0.0
        return in_contact & (self._data.current_contact_time < dt + abs_tol)

    def compute_first_air(self, dt: float, abs_tol: float = 1.0e-8) -> torch.Tensor:
        """(N, B) bodies that left contact within the last ``dt`` seconds."""
        self._need_air_time("compute_first_air")
        in_air = self._data.current_air_time > 0.0
        return in_air & (self._data.current_air_time < dt + abs_tol)

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> None:
        if not self._is_initialized:
            return
        mask = env_mask(env_ids, self.num_instances, self.device)
        d = self._data
        buffers = [d.net_forces_w, d.net_forces_w_history]
        if self.cfg.track_air_time:
            buffers += [d.current_air_time, d.last_air_time, d.current_contact_time, d.last_contact_time]
        for buffer in buffers:
            masked_copy_(buffer, mask, 0.0)

    def update(self, dt: float, force_recompute: bool = False) -> None:
        """Read this step's forces (called by the scene every physics step)."""
        if not self._is_initialized:
            return
        self._timestamp += dt
        if self.cfg.update_period > 0.0 and self._timestamp + 1e-9 < self.cfg.update_period and not force_recompute:
            return
        elapsed, self._timestamp = self._timestamp, 0.0
        d = self._data
        external = self._cfrc_ext[:, self._body_ids, 3:6] - self._xfrc[:, self._body_ids, 0:3]
        d.net_forces_w.copy_(external)
        if d.net_forces_w_history.shape[1] > 1:
            d.net_forces_w_history.copy_(torch.roll(d.net_forces_w_history, 1, dims=1))
        d.net_forces_w_history[:, 0] = external
        # every buffer is written in place: a step replayed as a CUDA graph reads and writes the
        # same tensors at each replay (a rebound attribute would leave the graph reading the old one)
        if self.cfg.track_pose:
            self._sim.physics.ensure_forward()  # body poses of the current state
            d.pos_w.copy_(self._xpos[:, self._body_ids] + self._sim.env_origins[:, None])
            d.quat_w.copy_(self._xquat[:, self._body_ids])
        if self.cfg.track_air_time:
            in_contact = torch.norm(external, dim=-1) > self.cfg.force_threshold
            first_contact = (d.current_air_time > 0.0) & in_contact
            first_air = (d.current_contact_time > 0.0) & ~in_contact
            d.last_air_time.copy_(torch.where(first_contact, d.current_air_time + elapsed, d.last_air_time))
            d.current_air_time.copy_(torch.where(in_contact, 0.0, d.current_air_time + elapsed))
            d.last_contact_time.copy_(torch.where(first_air, d.current_contact_time + elapsed, d.last_contact_time))
            d.current_contact_time.copy_(torch.where(in_contact, d.current_contact_time + elapsed, 0.0))

    # -- building -------------------------------------------------------------------------------

    def _initialize(self, sim) -> None:
        ids, names = find_sensor_bodies(sim.model, self.cfg.prim_path, f"ContactSensorCfg('{self.cfg.prim_path}')")
        names = [name.split("/", 1)[1] for name in names]  # "Robot/foot" -> "foot", as Isaac Lab names them
        self._body_ids = torch.tensor(ids, dtype=torch.long, device=self.device)
        self._body_names = names
        physics = sim.physics
        self._cfrc_ext, self._xfrc = physics.data("cfrc_ext"), physics.data("xfrc_applied")
        self._xpos, self._xquat = physics.data("xpos"), physics.data("xquat")
        n, b, dev = self.num_instances, len(ids), self.device
        d = self._data
        d.net_forces_w = torch.zeros(n, b, 3, device=dev)
        d.net_forces_w_history = torch.zeros(n, max(1, self.cfg.history_length), b, 3, device=dev)
        if self.cfg.track_pose:
            d.pos_w = torch.zeros(n, b, 3, device=dev)
            d.quat_w = torch.zeros(n, b, 4, device=dev)
        if self.cfg.track_air_time:
            d.current_air_time = torch.zeros(n, b, device=dev)
            d.last_air_time = torch.zeros(n, b, device=dev)
            d.current_contact_time = torch.zeros(n, b, device=dev)
            d.last_contact_time = torch.zeros(n, b, device=dev)
        super()._initialize(sim)

    def _need_air_time(self, what: str) -> None:
        if not self.cfg.track_air_time:
            raise RuntimeError(f"ContactSensor.{what} needs track_air_time=True in the ContactSensorCfg")


@configclass
class ContactSensorCfg(SensorBaseCfg):
    class_type: type = ContactSensor
    track_pose: bool = False
    track_air_time: bool = False
    force_threshold: float = 1.0
    """Newtons above which a body counts as touching (for air times)."""
    filter_prim_paths_expr: list[str] = list()
    visualizer_cfg: object | None = None
