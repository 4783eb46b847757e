"""Contact sensors: net contact force on each selected body, its history, and air/contact times.

The forces come from MuJoCo's own contact sensors, added to the model: one per sensor body with any
partner (the net contact force, ``net_forces_w``; only bodies with a geom that collides get one, the
others never touch anything and read zero, which saves MuJoCo Warp a pass over the contacts for each:
12 of the G1's 38 bodies) and, for chosen partners (``filter_prim_paths_expr``,
Isaac Lab's ``force_matrix_w``), one per (sensor body, partner) pair. Each sums, in the world frame,
the forces of the step's contacts that match it (``reduce="netforce"``: normal and friction), on
MuJoCo C and MuJoCo Warp alike. Only contacts count, as in PhysX: the body's external wrench
(``cfrc_ext``) would add the forces of equality constraints (a closed loop's rods, a weld) and
``xfrc_applied``.

The forces read are those of the physics step just taken: ``mj_step`` computes them from the state
it starts from and they drive it to the next state (what PhysX reports for its step too), so the
sensor needs no extra forward pass per physics step (one per substep would cost about half a step
more). The scene updates the sensor right after each physics step, before anything recomputes
derived quantities.

Body order: breadth first (by depth in the kinematic tree, then model order), the order of an
articulation's ``body_names``; a sensor over all of a robot's bodies lists them as the robot does.
Look bodies up by name (``find_bodies``, ``SceneEntityCfg(..., body_names=...)``) all the same.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import mujoco
import torch

from simlab.markers import CONTACT_SENSOR_MARKER_CFG, VisualizationMarkers, VisualizationMarkersCfg
from simlab.utils import configclass
from simlab.utils.env_mask import env_mask, masked_copy_
from simlab.utils.errors import ConfigError
from simlab.utils.string import resolve_matching_names

from .sensor_base import SensorBase, SensorBaseCfg, find_sensor_bodies, match_body_names, prim_path_in_model

_SENSOR_PREFIX = "simlab/contact"
_PREFIX_IDS = itertools.count()
# a MuJoCo contact sensor's settings (mjsSensor.intprm): its data (bit 1: force; bit 4: the point,
# for netforce the force-weighted centroid of the contacts), its reduction (3: netforce, the sum of
# the matching contacts' forces in the world frame) and one slot
_NET_FORCE_SENSOR = [2, 3, 1]
_NET_FORCE_AND_POINT_SENSOR = [2 | 16, 3, 1]


def _bodies_that_can_touch(spec: mujoco.MjSpec) -> set[str]:
    """Names of the bodies with a geom that collides (a nonzero contype or conaffinity, or one named by an
    explicit contact pair): a body without one is in no contact, ever."""
    paired = {name for pair in spec.pairs for name in (pair.geomname1, pair.geomname2)}
    return {g.parent.name for g in spec.geoms if g.contype or g.conaffinity or g.name in paired}


def _order_breadth_first(model: mujoco.MjModel, ids: list[int]) -> list[int]:
    from simlab.assets.root_body import breadth_first

    return breadth_first(model, ids, lambda b: b)


def _filter_partners(spec: mujoco.MjSpec, expr: str, owner: str) -> list[tuple[str, mujoco.mjtObj, str]]:
    """The contact partners ``expr`` names, as (name, MuJoCo object type, object name): bodies of
    assets (``{ENV_REGEX_NS}/Object``: its root body, ``{ENV_REGEX_NS}/Robot/.*_foot``: those), or
    static geometry of the world (``/World/ground``: the ground plane, or a terrain's geoms)."""
    bodies = list(spec.bodies)[1:]  # the world is no asset body
    names = [b.name for b in bodies]
    roots = {b.name for b in spec.worldbody.bodies}
    matched = [names[i] for i in match_body_names(names, roots, expr)]
    if matched:
        return [(name, mujoco.mjtObj.mjOBJ_BODY, name) for name in matched]
    path = prim_path_in_model(expr)
    static = [g.name for g in spec.worldbody.geoms if g.name == path or g.name.startswith(path + "/")]
    colliding = [g.name for g in spec.worldbody.geoms if g.contype or g.conaffinity]
    if len(static) == 1:
        return [(path, mujoco.mjtObj.mjOBJ_GEOM, static[0])]
    if static and set(colliding) <= set(static):  # every static geom that collides: the world body
        return [(path, mujoco.mjtObj.mjOBJ_BODY, "world")]
    if static:
        raise ValueError(
            f"{owner}: filter_prim_paths_expr '{expr}' names {len(static)} static geoms, but the world has other"
            f" colliding geoms too ({sorted(set(colliding) - set(static))[:5]}); a filter on static geometry"
            " must name one geom or all of it."
        )
    raise ValueError(
        f"{owner}: filter_prim_paths_expr '{expr}' matches no body and no static geom of the model; bodies: {names},"
        f" static geoms: {[g.name for g in spec.worldbody.geoms]}. Name an asset ('{{ENV_REGEX_NS}}/Object'),"
        " its bodies ('{ENV_REGEX_NS}/Robot/<body regex>') or static geometry ('/World/ground')."
    )


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
        """(N, B, M, 3) contact force on each body from each of the M partners that
        ``filter_prim_paths_expr`` names (world frame, normal and friction, as ``net_forces_w``);
        None without filters."""
        self.force_matrix_w_history: torch.Tensor | None = None
        """(N, T, B, M, 3) the last T values of ``force_matrix_w``, newest first."""
        self.contact_pos_w: torch.Tensor | None = None
        """(N, B, M, 3) where each body touches each partner: the force-weighted centre of their contact
        points, world frame; NaN where they do not touch (with ``track_contact_points``)."""


class ContactSensor(SensorBase):
    """Net contact forces of the bodies matched by ``prim_path`` (``{ENV_REGEX_NS}/Robot/.*``)."""

    cfg: ContactSensorCfg

    def __init__(self, cfg: ContactSensorCfg, scene=None):
        super().__init__(cfg, scene)
        self._partners: list[str] = []
        self._prefix = ""
        if cfg.track_contact_points and not cfg.filter_prim_paths_expr:
            raise ConfigError(
                f"ContactSensorCfg('{cfg.prim_path}').track_contact_points=True needs filter_prim_paths_expr: the"
                " points are reported per partner (as in Isaac Lab), e.g. filter_prim_paths_expr=['/World/ground']."
            )
        self._sim.add_build_callback(self._add_sensors)
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

    @property
    def filter_partner_names(self) -> list[str]:
        """The M partners of ``force_matrix_w``, in its order (Isaac Lab's order: by expression)."""
        return self._partners

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
        if d.force_matrix_w is not None:
            buffers += [d.force_matrix_w, d.force_matrix_w_history]
        if self.cfg.track_air_time:
            buffers += [self._current_times, self._last_times]
        for buffer in buffers:
            masked_copy_(buffer, mask, 0.0)
        if d.contact_pos_w is not None:
            masked_copy_(d.contact_pos_w, mask, torch.nan)  # no contact known yet

    def restart(self, mask: torch.Tensor) -> None:
        self.reset(mask)  # forces, their history and the air times: what reset clears, with no draw

    def update(self, dt: float, force_recompute: bool = False) -> None:
        """Read this step's forces (called by the scene every physics step)."""
        if not self._is_initialized:
            return
        self._timestamp += dt
        if self.cfg.update_period > 0.0 and self._timestamp + 1e-9 < self.cfg.update_period and not force_recompute:
            return
        elapsed, self._timestamp = self._timestamp, 0.0
        # Every buffer is written in place (a step replayed as a CUDA graph reads and writes the same
        # tensors at each replay), and with few ops: each is a kernel launch per physics step on the GPU.
        d = self._data
        if self._net_columns is None:  # every body has a MuJoCo sensor: one gather
            torch.index_select(self._sensordata, 1, self._net_index, out=self._net_flat)
        else:  # the others never touch anything and stay zero
            self._net_flat[:, self._net_columns] = self._sensordata.index_select(1, self._net_index)
        external = d.net_forces_w
        _push_history(d.net_forces_w_history, external)
        if d.force_matrix_w is not None:
            matrix = self._sensordata[:, self._filter_index]  # (N, B, M, 3)
            d.force_matrix_w.copy_(matrix)
            _push_history(d.force_matrix_w_history, matrix)
            if d.contact_pos_w is not None:
                touching = torch.linalg.vector_norm(matrix, dim=-1, keepdim=True) > 0.0
                points = self._sensordata[:, self._point_index] + self._sim.env_origins[:, None, None]
                d.contact_pos_w.copy_(points.masked_fill_(~touching, torch.nan))
        if self.cfg.track_pose:
            self._sim.physics.ensure_forward()  # body poses of the current state
            d.pos_w.copy_(self._xpos[:, self._body_ids] + self._sim.env_origins[:, None])
            d.quat_w.copy_(self._xquat[:, self._body_ids])
        if self.cfg.track_air_time:
            # air and contact times side by side, (N, 2, B): each phase (in the air, in contact) goes
            # on where its condition holds; where it ends after lasting a while, its length is kept
            touching = torch.linalg.vector_norm(external, dim=-1) > self.cfg.force_threshold
            goes_on = torch.eq(touching.unsqueeze(1), self._phase_is_contact)  # (N, 2, B): not touching, touching
            times = self._current_times + elapsed
            ended = (self._current_times > 0.0) > goes_on  # was running and stops now
            torch.where(ended, times, self._last_times, out=self._last_times)
            torch.mul(times, goes_on, out=self._current_times)

    # -- debug visualization: a sphere on every sensor body, red in contact ----------------------

    def _set_debug_vis_impl(self, debug_vis: bool) -> None:
        if debug_vis and not hasattr(self, "contact_visualizer"):
            self.contact_visualizer = VisualizationMarkers(self.cfg.visualizer_cfg)
        if hasattr(self, "contact_visualizer"):
            self.contact_visualizer.set_visibility(debug_vis)

    def _debug_vis_callback(self, event) -> None:
        # marker 0 ("contact") where the net force exceeds force_threshold, else 1 ("no_contact")
        force = torch.linalg.vector_norm(self._data.net_forces_w, dim=-1)
        indices = torch.where(force > self.cfg.force_threshold, 0, 1)
        self._sim.physics.ensure_forward()  # body poses of the current state
        origins = self._xpos[:, self._body_ids] + self._sim.env_origins[:, None]
        self.contact_visualizer.visualize(origins.reshape(-1, 3), marker_indices=indices.reshape(-1))

    # -- building -------------------------------------------------------------------------------

    def _add_sensors(self, spec: mujoco.MjSpec) -> None:
        """MuJoCo contact sensors: per body, the net force of its contacts with anything, and per (body,
        partner) the force the partner exerts on the body."""
        owner = f"ContactSensorCfg('{self.cfg.prim_path}')"
        bodies = list(spec.bodies)[1:]
        names = [b.name for b in bodies]
        roots = {b.name for b in spec.worldbody.bodies}
        sensor_bodies = [names[i] for i in match_body_names(names, roots, self.cfg.prim_path)]
        if not sensor_bodies and self.cfg.filter_prim_paths_expr:
            raise ValueError(f"{owner} prim_path '{self.cfg.prim_path}' matches no body of the model; bodies: {names}")
        self._prefix = f"{_SENSOR_PREFIX}{next(_PREFIX_IDS)}/"  # unique per sensor (some add no MuJoCo sensor)
        can_touch = _bodies_that_can_touch(spec)
        # object 1 unset: any partner; the force reported is the one on the body
        for body in (b for b in sensor_bodies if b in can_touch):
            spec.add_sensor(
                name=self._prefix + body,
                type=mujoco.mjtSensor.mjSENS_CONTACT,
                reftype=mujoco.mjtObj.mjOBJ_BODY,
                refname=body,
                intprm=_NET_FORCE_SENSOR,
            )
        if not self.cfg.filter_prim_paths_expr:
            return
        partners = [p for expr in self.cfg.filter_prim_paths_expr for p in _filter_partners(spec, expr, owner)]
        self._partners = [name for name, _, _ in partners]
        for body in sensor_bodies:
            for partner, objtype, objname in partners:
                name = self._filter_sensor_name(body, partner)
                spec.add_sensor(
                    name=name,
                    type=mujoco.mjtSensor.mjSENS_CONTACT,
                    objtype=objtype,  # object 1 exerts the force reported on object 2
                    objname=objname,
                    reftype=mujoco.mjtObj.mjOBJ_BODY,
                    refname=body,
                    intprm=_NET_FORCE_AND_POINT_SENSOR if self.cfg.track_contact_points else _NET_FORCE_SENSOR,
                )

    def _filter_sensor_name(self, body: str, partner: str) -> str:
        return f"{self._prefix}{body}|{partner}"

    def _initialize(self, sim) -> None:
        ids, names = find_sensor_bodies(sim.model, self.cfg.prim_path, f"ContactSensorCfg('{self.cfg.prim_path}')")
        ids = _order_breadth_first(sim.model, ids)
        names = [sim.model.body(b).name for b in ids]
        self._sensordata = sim.physics.data("sensordata")
        # each body's MuJoCo sensor (-1: the body cannot touch anything and has none)
        sensors = [mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_SENSOR, self._prefix + name) for name in names]
        sensing = [(j, sensor) for j, sensor in enumerate(sensors) if sensor >= 0]
        net = [int(sim.model.sensor_adr[sensor]) + i for _, sensor in sensing for i in range(3)]
        self._net_index = torch.tensor(net, dtype=torch.long, device=self.device)
        self._net_columns = None  # the columns of net_forces_w (as (N, B * 3)) the sensors fill: all
        if len(sensing) < len(names):
            columns = [3 * j + i for j, _ in sensing for i in range(3)]
            self._net_columns = torch.tensor(columns, dtype=torch.long, device=self.device)
        if self._partners:
            self._bind_filter_sensors(sim, names)
        names = [name.split("/", 1)[1] for name in names]  # "Robot/foot" -> "foot", as Isaac Lab names them
        self._body_ids = torch.tensor(ids, dtype=torch.long, device=self.device)
        self._body_names = names
        physics = sim.physics
        self._xpos, self._xquat = physics.data("xpos"), physics.data("xquat")
        n, b, dev = self.num_instances, len(ids), self.device
        d = self._data
        d.net_forces_w = torch.zeros(n, b, 3, device=dev)
        self._net_flat = d.net_forces_w.view(n, b * 3)  # what the update writes in place
        d.net_forces_w_history = torch.zeros(n, max(1, self.cfg.history_length), b, 3, device=dev)
        if self.cfg.track_pose:
            d.pos_w = torch.zeros(n, b, 3, device=dev)
            d.quat_w = torch.zeros(n, b, 4, device=dev)
        if self.cfg.track_air_time:
            # one (N, 2, B) buffer each for the current and the last phase times (air, contact): the
            # update then takes a few kernels for both; the data's tensors are views into them
            self._current_times = torch.zeros(n, 2, b, device=dev)
            self._last_times = torch.zeros(n, 2, b, device=dev)
            d.current_air_time, d.current_contact_time = self._current_times.unbind(1)
            d.last_air_time, d.last_contact_time = self._last_times.unbind(1)
            self._phase_is_contact = torch.tensor([[False], [True]], device=dev)  # the phases' order
        super()._initialize(sim)

    def _bind_filter_sensors(self, sim, body_names: list[str]) -> None:
        """Index of each (body, partner, xyz) value in ``sensordata``, bodies in the sensor's order."""
        model, m = sim.model, len(self._partners)
        addresses = []
        for body in body_names:
            for partner in self._partners:
                adr = int(model.sensor(self._filter_sensor_name(body, partner)).adr[0])
                addresses.append([adr, adr + 1, adr + 2])
        index = torch.tensor(addresses, dtype=torch.long, device=self.device).view(len(body_names), m, 3)
        self._filter_index = index
        if self.cfg.track_contact_points:  # the point follows the force in each sensor's values
            self._point_index = index + 3
            shape = (self.num_instances, len(body_names), m, 3)
            self._data.contact_pos_w = torch.full(shape, torch.nan, device=self.device)
        n, hist = self.num_instances, max(1, self.cfg.history_length)
        self._data.force_matrix_w = torch.zeros(n, len(body_names), m, 3, device=self.device)
        self._data.force_matrix_w_history = torch.zeros(n, hist, len(body_names), m, 3, device=self.device)

    def _need_air_time(self, what: str) -> None:
        if not self.cfg.track_air_time:
            raise RuntimeError(f"ContactSensor.{what} needs track_air_time=True in the ContactSensorCfg")


def _push_history(history: torch.Tensor, latest: torch.Tensor) -> None:
    """Shift ``history`` (N, T, ...) one step back in time and put ``latest`` first (two kernels)."""
    history.copy_(torch.cat([latest[:, None], history[:, :-1]], dim=1))


@configclass
class ContactSensorCfg(SensorBaseCfg):
    class_type: type = ContactSensor
    track_pose: bool = False
    track_air_time: bool = False
    force_threshold: float = 1.0
    """Newtons above which a body counts as touching (for air times)."""
    filter_prim_paths_expr: list[str] = list()
    track_contact_points: bool = False
    """Also report where each body touches each partner of ``filter_prim_paths_expr`` (``contact_pos_w``)."""
    max_contact_data_count_per_prim: int = 4
    """Isaac Lab's buffer size for PhysX's contact points; MuJoCo reports their force-weighted centre."""
    visualizer_cfg: VisualizationMarkersCfg = CONTACT_SENSOR_MARKER_CFG.replace(prim_path="/Visuals/ContactSensor")
    """The markers ``debug_vis`` draws on every sensor body: red in contact (above force_threshold), green not."""
