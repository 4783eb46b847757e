"""Articulations: robots made of bodies and hinge/slide joints, with a fixed or floating base.

State lives in the backend's MjData tensors; ``ArticulationData`` reads it through live views.
Positions and orientations that an articulation reads or writes are in the world frame with the
environment origins included (``scene.env_origins``), as in Isaac Lab, although each environment
is its own MuJoCo world centred on zero: the origins are added on read and removed on write.

Writes of state (root pose, joint positions, ...) reach the simulation at its next call; derived
quantities (body poses and velocities) are recomputed when next read.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import torch

import simlab.utils.math as math_utils
from simlab.actuators import ActuatorBase
from simlab.actuators.actuator_pd import per_joint_values
from simlab.utils.env_mask import is_mask, masked_copy_, rows
from simlab.utils.string import resolve_matching_names, resolve_matching_names_values
from simlab.utils.types import ArticulationActions

from .asset_base import EnvIds
from .body_properties_view import BodyPropertiesView
from .root_body import RootedAsset, RootedAssetData, breadth_first, contiguous


class Articulation(RootedAsset):
    """A robot of ``num_joints`` hinge/slide joints; see ``ArticulationCfg``."""

    def __init__(self, cfg):
        self.actuators: dict[str, ActuatorBase] = {}
        self._drive_gains: dict[str, tuple[float, float]] = {}  # joint -> the (kp, kd) its actuator got
        super().__init__(cfg)

    data: ArticulationData

    def _make_data(self, sim) -> ArticulationData:
        return ArticulationData(self, sim)

    # -- building ---------------------------------------------------------------------------------

    def _spec_joint_names(self, spec: mujoco.MjSpec) -> list[str]:
        return [
            j.name[len(self.prefix) :]
            for j in spec.joints
            if j.name.startswith(self.prefix) and j.type != mujoco.mjtJoint.mjJNT_FREE
        ]

    def _on_spawned(self, sim) -> None:
        """Add one MuJoCo actuator per actuated joint; see ``simlab.actuators.actuator_cfg``."""
        spec = sim.spec
        joint_names = self._spec_joint_names(spec)
        claimed: dict[str, str] = {}
        for group, act_cfg in self.cfg.actuators.items():
            _, names = resolve_matching_names(act_cfg.joint_names_expr, joint_names)
            for name in names:
                if name in claimed:
                    raise ValueError(
                        f"Joint '{name}' is driven by both actuator groups '{claimed[name]}' and '{group}'"
                    )
                claimed[name] = group
            implicit = act_cfg.class_type.is_implicit_model
            kp = per_joint_values(act_cfg.stiffness, names, 0.0)
            kd = per_joint_values(act_cfg.damping, names, 0.0)
            if implicit:  # gains left None: the MJCF joint's spring and damper become the drive's
                for gains, field, given in ((kp, "stiffness", act_cfg.stiffness), (kd, "damping", act_cfg.damping)):
                    if given is None:
                        for i, name in enumerate(names):
                            values = getattr(spec.joint(self.prefix + name), field)
                            gains[i], values[0] = float(values[0]), 0.0
            self._drive_gains.update({name: (kp[i], kd[i]) for i, name in enumerate(names)})
            # The simulation's cap: an implicit drive's one limit; an explicit model clips in torch
            # (``effort_limit``) and is capped only by an ``effort_limit_sim`` it sets.
            effort_cfg = act_cfg.effort_limit_sim
            if implicit and effort_cfg is None:
                effort_cfg = act_cfg.effort_limit
            effort = per_joint_values(effort_cfg, names, float("inf"))
            armature = per_joint_values(act_cfg.armature, names, None)
            friction = per_joint_values(act_cfg.friction, names, None)
            for i, name in enumerate(names):
                joint = spec.joint(self.prefix + name)
                if armature[i] is not None:
                    joint.armature = armature[i]
                if friction[i] is not None:
                    joint.frictionloss = friction[i]
                act = spec.add_actuator(name=self.prefix + name, target=self.prefix + name)
                act.trntype = mujoco.mjtTrn.mjTRN_JOINT
                act.gaintype = mujoco.mjtGain.mjGAIN_FIXED
                act.biastype = mujoco.mjtBias.mjBIAS_AFFINE
                act.gainprm[0] = 1.0
                if implicit:
                    act.biasprm[1], act.biasprm[2] = -kp[i], -kd[i]
                act.ctrllimited = mujoco.mjtLimited.mjLIMITED_FALSE
                if effort[i] != float("inf"):
                    act.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
                    act.forcerange = [-effort[i], effort[i]]

    def _on_compile(self, model: mujoco.MjModel) -> None:
        """Start every world at the configured joint positions (the simulation resets the worlds there)."""
        ids = self._model_joint_ids(model)
        names = [model.joint(j).name[len(self.prefix) :] for j in ids]
        if not names:
            return
        idx, _, values = resolve_matching_names_values(self.cfg.init_state.joint_pos, names)
        for i, value in zip(idx, values):
            model.qpos0[model.jnt_qposadr[ids[i]]] = value

    def _model_joint_ids(self, model: mujoco.MjModel) -> list[int]:
        ids = []
        for j in range(model.njnt):
            if not model.joint(j).name.startswith(self.prefix) or model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE:
                continue
            if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_BALL:
                raise ValueError(
                    f"Joint '{model.joint(j).name}' is a ball joint; articulations take hinge and slide joints"
                )
            ids.append(j)
        return breadth_first(model, ids, lambda j: int(model.jnt_bodyid[j]))

    def _initialize(self, sim) -> None:
        super()._initialize(sim)
        model, physics = sim.model, sim.physics
        n, dev = self.num_instances, self.device
        joint_ids = self._model_joint_ids(model)
        self._joint_names = [model.joint(j).name[len(self.prefix) :] for j in joint_ids]
        self._qpos_cols = contiguous([int(model.jnt_qposadr[j]) for j in joint_ids], dev)
        self._dof_cols = contiguous([int(model.jnt_dofadr[j]) for j in joint_ids], dev)
        self._qpos_index = torch.tensor([int(model.jnt_qposadr[j]) for j in joint_ids], dtype=torch.long, device=dev)
        self._dof_index = torch.tensor([int(model.jnt_dofadr[j]) for j in joint_ids], dtype=torch.long, device=dev)
        self._joint_model_ids = joint_ids
        num_joints = len(joint_ids)

        # Actuators: one MuJoCo actuator per actuated joint, named like the joint.
        data = self.data
        data.joint_stiffness = torch.zeros(n, num_joints, device=dev)
        data.joint_damping = torch.zeros(n, num_joints, device=dev)
        data.joint_effort_limits = torch.full((n, num_joints), float("inf"), device=dev)
        data.joint_velocity_limits = torch.full((n, num_joints), float("inf"), device=dev)
        dofs, f32 = self._dof_index.cpu(), torch.float32
        data.joint_armature = torch.tensor(model.dof_armature[dofs], dtype=f32, device=dev).repeat(n, 1)
        data.joint_friction_coeff = torch.tensor(model.dof_frictionloss[dofs], dtype=f32, device=dev).repeat(n, 1)
        actuated, ctrl_cols, self._explicit = [], [], []
        for group, act_cfg in self.cfg.actuators.items():
            ids, names = resolve_matching_names(act_cfg.joint_names_expr, self._joint_names)
            gains = torch.tensor([self._drive_gains.get(name, (0.0, 0.0)) for name in names], device=dev).reshape(-1, 2)
            actuator = act_cfg.class_type(act_cfg, names, ids, n, dev, stiffness=gains[:, 0], damping=gains[:, 1])
            self.actuators[group] = actuator
            data.joint_stiffness[:, ids] = actuator.stiffness
            data.joint_damping[:, ids] = actuator.damping
            data.joint_effort_limits[:, ids] = torch.minimum(actuator.effort_limit, actuator.effort_limit_sim)
            data.joint_velocity_limits[:, ids] = actuator.velocity_limit_sim
            actuated += ids
            ctrl_cols += [model.actuator(self.prefix + name).id for name in names]
            if not actuator.is_implicit_model:
                # its joints and MuJoCo actuators as slices where consecutive (views: no gather per step)
                own_ctrl = contiguous([model.actuator(self.prefix + name).id for name in names], dev)
                self._explicit.append((actuator, contiguous(list(ids), dev), own_ctrl))
        self._bind_explicit_efforts(model)
        # a host-side flag, so that the step of a robot without speed limits does no clamping
        self._speed_capped = bool(torch.isfinite(data.joint_velocity_limits).any())
        # qpos and qvel columns that are consecutive in another order than the joints' (breadth-first
        # names over a depth-first model, the Allegro Hand's): (their span, the joints in column order)
        self._qpos_span = column_span([int(model.jnt_qposadr[j]) for j in joint_ids], dev)
        self._dof_span = column_span([int(model.jnt_dofadr[j]) for j in joint_ids], dev)
        self._speed_cols, self._speed_order = self._dof_span or (self._dof_cols, slice(None))
        self._set_speed_bounds()
        order = sorted(range(len(actuated)), key=lambda k: actuated[k])
        self._actuated = contiguous([actuated[k] for k in order], dev)
        # whether some joints' ctrl holds implicit PD targets (explicit models write their own ctrl)
        self._any_implicit = any(a.is_implicit_model for a in self.actuators.values())
        self._ctrl_cols = contiguous([ctrl_cols[k] for k in order], dev)
        self._num_actuated = len(actuated)
        self._ctrl = physics.data("ctrl")
        self._actuator_force = physics.data("actuator_force")

        # Limits and defaults.
        ranges = torch.tensor(model.jnt_range[joint_ids], dtype=torch.float32, device=dev).reshape(num_joints, 2)
        limited = torch.tensor(model.jnt_limited[joint_ids].astype(bool), device=dev)
        ranges[~limited] = torch.tensor([-float("inf"), float("inf")], device=dev)
        data.joint_pos_limits = ranges.repeat(n, 1, 1)
        data.default_joint_pos_limits = data.joint_pos_limits.clone()
        data.soft_joint_pos_limits = soft_limits(data.joint_pos_limits, self.cfg.soft_joint_pos_limit_factor)
        data.soft_joint_vel_limits = data.joint_velocity_limits.clone()
        data.default_joint_stiffness = data.joint_stiffness.clone()
        data.default_joint_damping = data.joint_damping.clone()
        data.default_joint_pos = torch.zeros(n, num_joints, device=dev)
        data.default_joint_vel = torch.zeros(n, num_joints, device=dev)
        if num_joints:
            for attr, values in (
                ("default_joint_pos", self.cfg.init_state.joint_pos),
                ("default_joint_vel", self.cfg.init_state.joint_vel),
            ):
                idx, _, vals = resolve_matching_names_values(values, self._joint_names)
                getattr(data, attr)[:, idx] = torch.tensor(vals, dtype=torch.float32, device=dev)
        data.joint_pos_target = data.default_joint_pos.clone()
        data.joint_vel_target = torch.zeros(n, num_joints, device=dev)
        data.joint_effort_target = torch.zeros(n, num_joints, device=dev)
        data.joint_names = self._joint_names

    # -- Isaac Lab's API --------------------------------------------------------------------------

    @property
    def num_joints(self) -> int:
        return len(self._joint_names)

    @property
    def joint_names(self) -> list[str]:
        return self._joint_names

    @property
    def num_fixed_tendons(self) -> int:
        return 0

    @property
    def root_physx_view(self) -> ArticulationDynamicsView:
        """Isaac Lab's PhysX articulation view, for what task-space controllers read from it:
        ``get_jacobians``, ``get_generalized_mass_matrices``, the gravity and Coriolis forces."""
        view = self.__dict__.get("_dynamics_view")
        if view is None:
            view = self.__dict__["_dynamics_view"] = ArticulationDynamicsView(self)
        return view

    def find_joints(
        self, name_keys: str | Sequence[str], joint_subset: list[str] | None = None, preserve_order: bool = False
    ) -> tuple[list[int], list[str]]:
        """Indices and names of the joints matching names or regexes (errors list what exists)."""
        joint_subset = self.joint_names if joint_subset is None else joint_subset
        return resolve_matching_names(name_keys, joint_subset, preserve_order)

    def reset(self, env_ids: EnvIds = None) -> None:
        super().reset(env_ids)
        for actuator in self.actuators.values():
            actuator.reset(env_ids)

    def restart(self, mask: torch.Tensor) -> None:
        super().restart(mask)
        for actuator in self.actuators.values():
            actuator.restart(mask)

    def write_data_to_sim(self) -> None:
        """Turn joint targets into MuJoCo controls and apply external wrenches."""
        super().write_data_to_sim()
        if self._speed_capped:
            self._cap_joint_speed()
        if not self._num_actuated:
            return
        d = self.data
        if self._any_implicit:
            # Implicit: ctrl = kp q* + kd qd* + tau_ff (the PD bias lives in the model; see actuator_cfg),
            # in two fused multiply-adds (kernels run before every physics step)
            ctrl = torch.addcmul(d.joint_effort_target, d.joint_damping, d.joint_vel_target)
            ctrl.addcmul_(d.joint_stiffness, d.joint_pos_target)
            self._ctrl[:, self._ctrl_cols] = ctrl[:, self._actuated]
        if not self._explicit:
            return
        # Explicit models write their joints' ctrl: the torque they compute.
        joint_pos, joint_vel = d.joint_pos, d.joint_vel
        for (actuator, j, ctrl_cols), part in zip(self._explicit, self._explicit_parts):
            targets = ArticulationActions(
                d.joint_pos_target[:, j], d.joint_vel_target[:, j], d.joint_effort_target[:, j], actuator.joint_indices
            )
            efforts = actuator.compute(targets, joint_pos[:, j], joint_vel[:, j]).joint_efforts
            if part is None:
                self._ctrl[:, ctrl_cols] = efforts
            elif efforts is not part:  # a model that returns another tensor than its applied_effort
                part.copy_(efforts)
        if self._explicit_efforts is not None:
            self._ctrl[:, self._explicit_ctrl_cols] = self._explicit_efforts

    def _bind_explicit_efforts(self, model: mujoco.MjModel) -> None:
        """Several explicit models (Spot's hips and knees): their ``applied_effort`` become views side by side
        in one buffer, written to MuJoCo's ctrl in one kernel per physics step instead of one per model."""
        self._explicit_parts: list[torch.Tensor | None] = [None] * len(self._explicit)
        self._explicit_efforts = None
        if len(self._explicit) < 2:
            return
        models = [actuator for actuator, _, _ in self._explicit]
        widths = [actuator.num_joints for actuator in models]
        self._explicit_efforts = torch.zeros(self.num_instances, sum(widths), device=self.device)
        self._explicit_parts = list(self._explicit_efforts.split(widths, dim=1))
        for actuator, part in zip(models, self._explicit_parts):
            part.copy_(actuator.applied_effort)
            actuator.applied_effort = part  # the model clips into it (out=) every physics step
        ctrl = [model.actuator(self.prefix + name).id for actuator in models for name in actuator.joint_names]
        self._explicit_ctrl_cols = contiguous(ctrl, self.device)

    # joint state ---------------------------------------------------------------------------------

    def write_joint_state_to_sim(self, position, velocity, joint_ids=None, env_ids: EnvIds = None) -> None:
        self.write_joint_position_to_sim(position, joint_ids, env_ids)
        self.write_joint_velocity_to_sim(velocity, joint_ids, env_ids)

    def write_joint_position_to_sim(self, position, joint_ids=None, env_ids: EnvIds = None) -> None:
        if not self._write_span(self._qpos, self._qpos_span, joint_ids, env_ids, position):
            self._write_cols(self._qpos, self._cols(self._qpos_cols, self._qpos_index, joint_ids), env_ids, position)
        self._physics.mark_stale(self._env_index(env_ids))

    def write_joint_velocity_to_sim(self, velocity, joint_ids=None, env_ids: EnvIds = None) -> None:
        if not self._write_span(self._qvel, self._dof_span, joint_ids, env_ids, velocity):
            self._write_cols(self._qvel, self._cols(self._dof_cols, self._dof_index, joint_ids), env_ids, velocity)
        self._physics.mark_stale(self._env_index(env_ids))

    @staticmethod
    def _write_span(dst: torch.Tensor, span, joint_ids, env_ids: EnvIds, values) -> bool:
        """Every joint's column by a mask where the columns are consecutive in another order (``span``):
        the values put in column order and copied in place (a gather and a select, instead of a gather,
        a select and a scatter). False where this does not apply."""
        if span is None or joint_ids is not None or not is_mask(env_ids):
            return False
        if not isinstance(values, torch.Tensor) or values.dim() != 2:
            return False
        cols, order = span
        masked_copy_(dst[:, cols], env_ids.to(dst.device), values[:, order])
        return True

    # joint targets -------------------------------------------------------------------------------

    def set_joint_position_target(self, target, joint_ids=None, env_ids: EnvIds = None) -> None:
        self._write_cols(self.data.joint_pos_target, self._joint_index(joint_ids), env_ids, target)

    def set_joint_velocity_target(self, target, joint_ids=None, env_ids: EnvIds = None) -> None:
        self._write_cols(self.data.joint_vel_target, self._joint_index(joint_ids), env_ids, target)

    def set_joint_effort_target(self, target, joint_ids=None, env_ids: EnvIds = None) -> None:
        self._write_cols(self.data.joint_effort_target, self._joint_index(joint_ids), env_ids, target)

    # joint properties (per world; what randomization events change) ------------------------------

    def write_joint_stiffness_to_sim(self, stiffness, joint_ids=None, env_ids: EnvIds = None) -> None:
        self._write_cols(self.data.joint_stiffness, self._joint_index(joint_ids), env_ids, stiffness)
        self._sync_actuator_model(1, self.data.joint_stiffness, env_ids)
        self._sync_explicit_gains("stiffness", self.data.joint_stiffness)

    def write_joint_damping_to_sim(self, damping, joint_ids=None, env_ids: EnvIds = None) -> None:
        self._write_cols(self.data.joint_damping, self._joint_index(joint_ids), env_ids, damping)
        self._sync_actuator_model(2, self.data.joint_damping, env_ids)
        self._sync_explicit_gains("damping", self.data.joint_damping)

    def write_joint_effort_limit_to_sim(self, limits, joint_ids=None, env_ids: EnvIds = None) -> None:
        self._write_cols(self.data.joint_effort_limits, self._joint_index(joint_ids), env_ids, limits)
        env = self._env_index(env_ids)
        limit = self.data.joint_effort_limits[env][:, self._actuated].clamp(max=1e9)
        forcerange = self._physics.model_field("actuator_forcerange")
        self._physics.model_field("actuator_forcelimited")[env, self._ctrl_cols] = 1
        forcerange[env, self._ctrl_cols] = torch.stack([-limit, limit], dim=-1)

    def write_joint_velocity_limit_to_sim(self, limits, joint_ids=None, env_ids: EnvIds = None) -> None:
        """The joint speed cap of the simulation (PhysX's max joint velocity), applied before every physics step."""
        self._write_cols(self.data.joint_velocity_limits, self._joint_index(joint_ids), env_ids, limits)
        self._speed_capped = True
        self._set_speed_bounds()

    def _set_speed_bounds(self) -> None:
        """The speed cap's bounds in the order of ``qvel``'s columns (``_speed_cols``): a robot whose
        joints are a permutation of consecutive columns (breadth-first names over a depth-first model,
        the Allegro Hand's) is clamped in place over those columns, one kernel per physics step."""
        limit = self.data.joint_velocity_limits[:, self._speed_order]
        self._speed_bounds = (-limit, limit)

    def _cap_joint_speed(self) -> None:
        """Clip joint velocities to ``joint_velocity_limits`` before the physics step.

        MuJoCo has no joint speed limit; PhysX clamps a joint's velocity to its max joint velocity in
        the solver. Clipping the state before each step is the closest MuJoCo-side equivalent: the
        step then starts within the limit (the step itself recomputes everything from qpos and qvel).
        """
        lower, upper = self._speed_bounds
        cols = self._speed_cols
        if isinstance(cols, slice):  # a view of qvel: clamped in place
            torch.clamp(self._qvel[:, cols], lower, upper, out=self._qvel[:, cols])
        else:
            self._qvel[:, cols] = torch.clamp(self._qvel[:, cols], lower, upper)

    def write_joint_armature_to_sim(self, armature, joint_ids=None, env_ids: EnvIds = None) -> None:
        self._write_cols(self.data.joint_armature, self._joint_index(joint_ids), env_ids, armature)
        self._write_model_dofs("dof_armature", self.data.joint_armature, env_ids)

    def write_joint_friction_coefficient_to_sim(self, friction, joint_ids=None, env_ids: EnvIds = None) -> None:
        self._write_cols(self.data.joint_friction_coeff, self._joint_index(joint_ids), env_ids, friction)
        self._write_model_dofs("dof_frictionloss", self.data.joint_friction_coeff, env_ids)

    def write_joint_position_limit_to_sim(self, limits, joint_ids=None, env_ids: EnvIds = None) -> None:
        env, cols = self._env_index(env_ids), self._joint_index(joint_ids)
        self._write_cols(self.data.joint_pos_limits, cols, env_ids, limits)
        self.data.soft_joint_pos_limits = soft_limits(self.data.joint_pos_limits, self.cfg.soft_joint_pos_limit_factor)
        jnt_range = self._physics.model_field("jnt_range")
        ids = self._index_tensor(self._joint_model_ids)
        if is_mask(env):  # every row, kept where the mask is clear: no read back to the host
            old = jnt_range[:, ids]
            jnt_range[:, ids] = torch.where(rows(env, old), self.data.joint_pos_limits.clamp(-1e9, 1e9), old)
            return
        limits = self.data.joint_pos_limits[env].clamp(-1e9, 1e9)
        if not isinstance(env, slice):  # env rows by index, broadcast against the joint columns
            env = env[:, None]
        jnt_range[env, ids] = limits

    # -- helpers ----------------------------------------------------------------------------------

    def _joint_index(self, joint_ids):
        if joint_ids is None or (isinstance(joint_ids, slice) and joint_ids == slice(None)):
            return slice(None)
        if isinstance(joint_ids, torch.Tensor):
            return joint_ids.to(device=self.device, dtype=torch.long)
        if isinstance(joint_ids, slice):
            return joint_ids
        return self._index_tensor(joint_ids)

    def _cols(self, cols, index: torch.Tensor, joint_ids):
        """State columns (qpos or qvel) of the selected joints."""
        sel = self._joint_index(joint_ids)
        if isinstance(sel, slice):
            return cols
        if not isinstance(joint_ids, (list, tuple)):
            return index[sel]
        # Joints named by index lists (what find_joints and SceneEntityCfg give) recur every step:
        # keep their columns instead of gathering them again. Every code path of an env step runs
        # eagerly before a graph capture (resets are by mask, never skipped), so the cache is
        # filled outside any capture.
        cache = self.__dict__.setdefault("_cols_cache", {})
        key = (id(index), tuple(int(i) for i in joint_ids))
        if key not in cache:
            cache[key] = index[sel]
        return cache[key]

    def _sync_explicit_gains(self, name: str, gains: torch.Tensor) -> None:
        """Explicit models compute with their own gains (Isaac Lab's): keep them equal to the data's."""
        for actuator, joints, _ in self._explicit:
            getattr(actuator, name).copy_(gains[:, joints])

    def _sync_actuator_model(self, bias_term: int, gains: torch.Tensor, env_ids: EnvIds) -> None:
        """Implicit actuators hold their PD gains in the model's bias: keep it per world in step."""
        implicit = [a for a in self.actuators.values() if a.is_implicit_model]
        if not implicit:
            return
        env = self._env_index(env_ids)
        biasprm = self._physics.model_field("actuator_biasprm")
        if is_mask(env):  # every row, kept where the mask is clear: no read back to the host
            for actuator in implicit:
                ctrl_cols = self._actuator_ctrl_cols(actuator)
                old = biasprm[:, ctrl_cols, bias_term]
                new = -gains[:, actuator.joint_indices]
                biasprm[:, ctrl_cols, bias_term] = torch.where(rows(env, old), new, old)
            return
        selected = biasprm[env] if not isinstance(env, slice) else biasprm
        for actuator in implicit:
            values = -gains[env][:, actuator.joint_indices]
            selected[:, self._actuator_ctrl_cols(actuator), bias_term] = values
        if not isinstance(env, slice):
            biasprm[env] = selected

    def _actuator_ctrl_cols(self, actuator: ActuatorBase) -> torch.Tensor:
        """The MuJoCo actuators of ``actuator``'s joints (a device tensor made once)."""
        return self._index_tensor(self._sim.model.actuator(self.prefix + name).id for name in actuator.joint_names)

    def _write_model_dofs(self, field: str, values: torch.Tensor, env_ids: EnvIds) -> None:
        env = self._env_index(env_ids)
        target = self._physics.model_field(field)
        if is_mask(env):  # every row, kept where the mask is clear: no read back to the host
            old = target[:, self._dof_index]
            target[:, self._dof_index] = torch.where(rows(env, old), values, old)
        elif isinstance(env, slice):
            target[:, self._dof_index] = values
        else:
            target[env[:, None], self._dof_index] = values[env]


def column_span(columns: list[int], device) -> tuple[slice, torch.Tensor] | None:
    """For columns that are consecutive in another order: their span and, for each column in it, which
    of ``columns`` it is; None otherwise (in order already, or with gaps)."""
    first = min(columns, default=0)
    if columns == list(range(first, first + len(columns))) or sorted(columns) != list(
        range(first, first + len(columns))
    ):
        return None
    order = sorted(range(len(columns)), key=columns.__getitem__)
    return slice(first, first + len(columns)), torch.tensor(order, dtype=torch.long, device=device)


class ArticulationDynamicsView(BodyPropertiesView):
    """The parts of PhysX's ``ArticulationView`` that controllers use, from MuJoCo's forward pass.

    Shapes follow PhysX: Jacobians are ``(num_envs, num_bodies, 6, num_dofs)`` with rows
    ``[linear; angular]`` velocity of each body's frame origin in the world frame; for a fixed base
    the root body is left out (body ``i`` of the articulation is row ``i - 1``) and the dofs are the
    joints; a floating base has 6 more dofs first (root linear then angular velocity, world frame).
    """

    def __init__(self, articulation: Articulation):
        from simlab.sim.dynamics import TreeDynamics

        super().__init__(articulation)
        a = articulation
        model = a._sim.model
        self._fixed = a.is_fixed_base
        bodies = a._body_ids[1:] if self._fixed else a._body_ids
        dofs = [int(model.jnt_dofadr[j]) for j in a._joint_model_ids]
        self._root_quat = None
        if not self._fixed:
            root_dof = int(a._root_lin_cols.start)
            dofs = list(range(root_dof, root_dof + 6)) + dofs
            self._root_quat = lambda: a._qpos[:, a._root_quat_cols]
        self._tree = TreeDynamics(a._physics, model, bodies, dofs)
        self.count = a.num_instances
        self.max_dofs = len(dofs)
        self.max_links = len(bodies) + int(self._fixed)

    def get_dof_limits(self) -> torch.Tensor:
        """(num_envs, num_joints, 2): each joint's lower and upper position limit (the model's range)."""
        return self._asset.data.joint_pos_limits.clone()

    def get_jacobians(self) -> torch.Tensor:
        jac = self._tree.jacobians()
        if self._root_quat is not None:
            # MuJoCo's free joint turns at a body-frame angular velocity; PhysX's at a world-frame one.
            rot = math_utils.matrix_from_quat(self._root_quat())
            jac = jac.clone()
            jac[..., 3:6] = jac[..., 3:6] @ rot.transpose(-1, -2)[:, None]
        return jac

    def get_generalized_mass_matrices(self) -> torch.Tensor:
        mass = self._tree.mass_matrix()
        if self._root_quat is not None:
            rot = self._free_rotation()
            mass = rot.transpose(-1, -2) @ mass @ rot
        return mass

    def get_gravity_compensation_forces(self) -> torch.Tensor:
        return self._to_world_dofs(self._tree.gravity_forces())

    def get_coriolis_and_centrifugal_compensation_forces(self) -> torch.Tensor:
        return self._to_world_dofs(self._tree.coriolis_and_centrifugal_forces())

    # older PhysX names
    get_mass_matrices = get_generalized_mass_matrices
    get_generalized_gravity_forces = get_gravity_compensation_forces
    get_coriolis_and_centrifugal_forces = get_coriolis_and_centrifugal_compensation_forces

    def _free_rotation(self) -> torch.Tensor:
        """(N, D, D): maps PhysX's dof velocities (world-frame root rotation) to MuJoCo's."""
        n, d = self.count, self.max_dofs
        rot = torch.eye(d, device=self._tree._dof_index.device).repeat(n, 1, 1)
        rot[:, 3:6, 3:6] = math_utils.matrix_from_quat(self._root_quat()).transpose(-1, -2)
        return rot

    def _to_world_dofs(self, forces: torch.Tensor) -> torch.Tensor:
        if self._root_quat is None:
            return forces
        return (self._free_rotation().transpose(-1, -2) @ forces[..., None])[..., 0]


def soft_limits(limits: torch.Tensor, factor: float) -> torch.Tensor:
    """Limits shrunk about their middle by ``factor``; infinite limits stay infinite."""
    mean = (limits[..., 0] + limits[..., 1]) / 2
    half = (limits[..., 1] - limits[..., 0]) / 2 * factor
    soft = torch.stack([mean - half, mean + half], dim=-1)
    return torch.where(torch.isfinite(limits), soft, limits)


class ArticulationData(RootedAssetData):
    """Live joint state plus the per-env joint properties the articulation keeps in torch."""

    def __init__(self, asset: Articulation, sim):
        super().__init__(asset, sim)
        self._qacc = sim.physics.data("qacc")
        self.joint_names: list[str] = []
        # Filled by Articulation._initialize: (num_envs, num_joints[, 2]) tensors.
        self.default_joint_pos: torch.Tensor
        self.default_joint_vel: torch.Tensor
        self.joint_pos_target: torch.Tensor
        self.joint_vel_target: torch.Tensor
        self.joint_effort_target: torch.Tensor
        self.joint_stiffness: torch.Tensor
        self.joint_damping: torch.Tensor
        self.joint_armature: torch.Tensor
        self.joint_friction_coeff: torch.Tensor
        self.joint_pos_limits: torch.Tensor
        self.soft_joint_pos_limits: torch.Tensor
        self.joint_velocity_limits: torch.Tensor
        self.soft_joint_vel_limits: torch.Tensor
        self.joint_effort_limits: torch.Tensor

    @property
    def joint_pos(self) -> torch.Tensor:
        a = self._asset
        return a._qpos[:, a._qpos_cols]

    @property
    def joint_vel(self) -> torch.Tensor:
        a = self._asset
        return a._qvel[:, a._dof_cols]

    # joint_acc and applied_torque are what the last physics step applied (as Isaac Lab's, whose
    # acceleration is the last step's velocity change and whose torque the actuators computed before
    # it): MuJoCo leaves them from that step's forward, so they are read without a new forward, which
    # would recompute them at the new state (and cost a forward per env step when a reward reads them).

    @property
    def joint_acc(self) -> torch.Tensor:
        """Joint accelerations of the last physics step."""
        a = self._asset
        return self._qacc[:, a._dof_cols]

    @property
    def applied_torque(self) -> torch.Tensor:
        """Torque MuJoCo's actuators applied in the last step, after clamping (0 where unactuated)."""
        a = self._asset
        torque = torch.zeros_like(self.joint_effort_target)
        torque[:, a._actuated] = a._actuator_force[:, a._ctrl_cols]
        return torque

    @property
    def computed_torque(self) -> torch.Tensor:
        """Torque the actuator models ask for, before their limits (an explicit model's ``computed_effort``)."""
        torque = (
            self.joint_stiffness * (self.joint_pos_target - self.joint_pos)
            + self.joint_damping * (self.joint_vel_target - self.joint_vel)
            + self.joint_effort_target
        )
        for actuator, joints, _ in self._asset._explicit:
            torque[:, joints] = actuator.computed_effort
        return torque

    @property
    def body_incoming_joint_wrench_b(self) -> torch.Tensor:
        """The wrench each body receives from its parent through its joint, ``[force, torque]`` in the
        body's frame about its origin: (num_envs, num_bodies, 6). The root's is the wrench from the
        world (through its free joint: zero; through a fixed base: what holds the robot).

        MuJoCo's ``cfrc_int`` (the interaction force with the parent, computed by the post-constraint
        pass: in every forward pass of a model compiled with it, as ``mdp.body_incoming_wrench`` and
        ``sim_utils.compute_body_interaction_forces`` do, else by the backend when read), moved from
        the tree's centre of mass to the body's origin and rotated into the body's frame. It is what
        MuJoCo's force and torque sensors on a site at the body's origin read, at the current state
        (worlds whose state changed since their last forward pass are forwarded first).

        It is PhysX's ``get_link_incoming_joint_force()``, which Isaac Lab's in-hand tasks read for the
        fingertips: there a body with ``disable_gravity`` is weightless. Here that is MuJoCo's gravity
        compensation, a joint-space force that ``cfrc_int`` does not see: the joints would still carry
        the body's weight. The compensating force on the body and the bodies it carries (at their
        centres of mass) is taken out, so a weightless fingertip at rest reads zero, as in PhysX."""
        a = self._asset
        # cfrc_int comes from the whole forward pass (post_constraint forwards stale worlds): a
        # kinematics-only refresh (the cuda backend's ensure_kinematics) would pair the new poses
        # with the last step's forces
        cfrc_int = a._physics.post_constraint("cfrc_int")
        ids = a._body_index
        spatial = cfrc_int[:, ids]  # [torque about the tree's centre of mass, force], world axes
        force = spatial[..., 3:6]
        offset = self._xpos[:, ids] - self._subtree_com[:, self._rootids]
        torque = spatial[..., 0:3] - torch.linalg.cross(offset, force, dim=-1)
        carried = self._gravcomp_carried()
        if carried is not None:  # what the compensation holds up is no load on the joints (PhysX: weightless)
            physics = a._physics
            mass = physics.per_world_model_field("body_mass")
            gravity = physics.per_world_model_field("opt.gravity")
            mass = self._model_mass if mass is None else mass  # (1 or num_envs, nbody)
            gravity = self._model_gravity if gravity is None else gravity  # (1 or num_envs, 3)
            weight = carried[None] * mass[:, None, :]  # (envs, bodies, nbody): the compensated mass each carries
            held = -weight.sum(-1, keepdim=True) * gravity[:, None, :]  # the compensating force, summed
            moment = weight @ self._xipos - weight.sum(-1, keepdim=True) * self._xpos[:, ids]  # mass x lever arm
            force = force - held
            torque = torque - torch.linalg.cross(moment, -gravity[:, None, :].expand_as(moment), dim=-1)
        quat = self._xquat[:, ids]
        return torch.cat([math_utils.quat_apply_inverse(quat, force), math_utils.quat_apply_inverse(quat, torque)], -1)

    def _gravcomp_carried(self) -> torch.Tensor | None:
        """(num_bodies, nbody): the gravity compensation of model body b where the articulation's body k
        carries it (b is k or below k); None when no body it carries is compensated (known once: the
        step reads nothing back from the device)."""
        if not hasattr(self, "_carried"):
            a = self._asset
            model, dev = a._sim.model, a.device
            parents = model.body_parentid
            carried = torch.zeros(len(a._body_ids), model.nbody)
            for row, root in enumerate(int(i) for i in a._body_ids):
                for b in range(model.nbody):
                    up = b
                    while up > root:  # MuJoCo numbers a parent before its children
                        up = int(parents[up])
                    if up == root:
                        carried[row, b] = float(model.body_gravcomp[b])
            self._carried = carried.to(dev) if bool(carried.any()) else None
            self._model_mass = torch.tensor(model.body_mass, dtype=torch.float32, device=dev)[None]
            self._model_gravity = torch.tensor(model.opt.gravity, dtype=torch.float32, device=dev)[None]
        return self._carried

    # Isaac Lab's older names.
    joint_limits = property(lambda self: self.joint_pos_limits)
    joint_vel_limits = property(lambda self: self.joint_velocity_limits)
    joint_friction = property(lambda self: self.joint_friction_coeff)


def __getattr__(name: str):
    """``from simlab.assets.articulation import ArticulationCfg``, as Isaac Lab's package exports it
    (the config imports this module, so it is looked up on first use)."""
    if name == "ArticulationCfg":
        from .articulation_cfg import ArticulationCfg

        return ArticulationCfg
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
