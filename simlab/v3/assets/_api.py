"""Isaac Lab 3.0's asset API on simlab's assets: its data view, its ``_index`` / ``_mask`` writers and
its actuator command collection, all mapped onto simlab's 2.x methods.

The same asset serves 2.x code and 3.0 code: the data fields are simlab's tensors ``(w, x, y, z)``
with 3.0's ``.torch`` ``(x, y, z, w)`` on them (:mod:`simlab.v3._proxy`), and the 3.0 names
(``write_root_pose_to_sim_index``, ``actuators.target_command``, ``data.default_root_pose``) exist
only in 3.0's spelling, so every value they take or give is converted at this boundary, once.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable
from typing import Any

import torch

import simlab.utils.math as math_utils
from simlab.v3._proxy import ProxyTensor, as_v3, proxy

__all__ = [
    "ActuatorCollection",
    "AssetDataView",
    "BodyPropertyWriters",
    "BodyWriters",
    "JointWriters",
    "RootWriters",
    "TargetCommand",
]


# -- data ------------------------------------------------------------------------------------------

# Isaac Lab 3.0's data names that simlab's data spells otherwise: name -> how to read it from simlab's data.
RENAMED_DATA: dict[str, Callable[[Any], torch.Tensor]] = {
    "default_root_pose": lambda d: d.default_root_state[:, :7],  # 3.0 split default_root_state
    "default_root_vel": lambda d: d.default_root_state[:, 7:],
}


class AssetDataView:
    """An asset's data as Isaac Lab 3.0 reads it: every public tensor a :class:`ProxyTensor` (a tensor
    for 2.x code, ``.torch`` / ``.warp`` for 3.0 code), plus 3.0's renamed fields. Assignments go to
    simlab's data (the articulation sets its joint properties there)."""

    __slots__ = ("_data",)
    renamed: dict[str, Callable[[Any], torch.Tensor]] = RENAMED_DATA

    def __init__(self, data: Any):
        object.__setattr__(self, "_data", data)

    def __getattr__(self, name: str) -> Any:
        data = object.__getattribute__(self, "_data")
        if name.startswith("_"):
            return getattr(data, name)
        read = type(self).renamed.get(name)
        return proxy(name, read(data) if read is not None else getattr(data, name))

    def __setattr__(self, name: str, value: Any) -> None:
        setattr(object.__getattribute__(self, "_data"), name, value)

    def __dir__(self) -> list[str]:
        return sorted({*dir(object.__getattribute__(self, "_data")), *type(self).renamed})


# -- writers ---------------------------------------------------------------------------------------


def _simlab_order(value: Any, quat_at: int | None) -> Any:
    """A value 3.0 code wrote, as simlab's writer takes it: quaternion columns to (w, x, y, z)."""
    value = as_v3(value)
    if quat_at is None:
        return value
    value = torch.as_tensor(value)
    out = value.clone()
    out[..., quat_at : quat_at + 4] = torch.roll(value[..., quat_at : quat_at + 4], 1, dims=-1)
    return out


def _bool_mask(mask: Any, size: int, what: str, device: torch.device | str) -> torch.Tensor:
    mask = torch.as_tensor(as_v3(mask), device=device)
    if mask.dtype != torch.bool or mask.shape != (size,):
        raise ValueError(f"{what} must be a bool mask of shape ({size},), got {mask.dtype} {tuple(mask.shape)}")
    return mask


def _take(method: str, kwargs: dict[str, Any], names: tuple[str, ...], selectors: tuple[str, ...]) -> list[Any]:
    """The data arguments ``names`` of a 3.0 writer (keyword-only, as 3.0's), with one-line errors."""
    missing = [n for n in names if n not in kwargs]
    unknown = sorted(set(kwargs) - set(names) - set(selectors) - {"skip_forward", "warn_limit_violation"})
    if missing or unknown:
        allowed = ", ".join(f"{n}=" for n in (*names, *selectors))
        problem = f"missing {missing}" if missing else f"unexpected {unknown}"
        raise TypeError(f"{method}(): {problem}; Isaac Lab 3.0's {method} takes the keywords {allowed}")
    return [kwargs[n] for n in names]


def _index_writer(base: str, names: tuple[str, ...], quat_at: int | None, item: str | None) -> Callable:
    """``<base>_index(*, <names>, [<item>_ids=], env_ids=)``: simlab's ``<base>(*values, env_ids=, [<item>_ids=])``."""
    method = f"{base}_index"
    selectors = ("env_ids",) if item is None else (f"{item}_ids", "env_ids")

    def write(self, **kwargs: Any) -> None:
        values = [_simlab_order(v, quat_at) for v in _take(method, kwargs, names, selectors)]
        items = {} if item is None else {f"{item}_ids": as_v3(kwargs.get(f"{item}_ids"))}
        getattr(self, base)(*values, env_ids=as_v3(kwargs.get("env_ids")), **items)

    write.__name__ = method
    write.__doc__ = f"Isaac Lab 3.0's ``{method}``: simlab's ``{base}`` with env (and {item or 'no'}) indices."
    return write


def _mask_writer(base: str, names: tuple[str, ...], quat_at: int | None, item: str | None) -> Callable:
    """``<base>_mask(*, <names>, [<item>_mask=], env_mask=)``: full data (a row per env), a bool env mask."""
    method = f"{base}_mask"
    selectors = ("env_mask",) if item is None else (f"{item}_mask", "env_mask")

    def write(self, **kwargs: Any) -> None:
        values = [_simlab_order(v, quat_at) for v in _take(method, kwargs, names, selectors)]
        env_mask = kwargs.get("env_mask")
        env = None if env_mask is None else _bool_mask(env_mask, self.num_instances, "env_mask", self.device)
        if item is None:
            getattr(self, base)(*values, env_ids=env)
            return
        ids = None
        item_mask = kwargs.get(f"{item}_mask")
        if item_mask is not None:  # full data: keep the selected columns (found on the host)
            count = self.num_joints if item == "joint" else self.num_bodies
            selected = _bool_mask(item_mask, count, f"{item}_mask", self.device)
            ids = selected.nonzero().flatten().tolist()
            values = [v[:, selected] if isinstance(v, torch.Tensor) and v.dim() > 1 else v for v in values]
        getattr(self, base)(*values, env_ids=env, **{f"{item}_ids": ids})

    write.__name__ = method
    write.__doc__ = f"Isaac Lab 3.0's ``{method}``: simlab's ``{base}`` with a bool env mask (full data)."
    return write


def _add_writers(cls: type, table: dict[str, tuple[tuple[str, ...], int | None]], item: str | None) -> type:
    for base, (names, quat_at) in table.items():
        setattr(cls, f"{base}_index", _index_writer(base, names, quat_at, item))
        setattr(cls, f"{base}_mask", _mask_writer(base, names, quat_at, item))
    return cls


# 3.0 writer (without _index / _mask) -> (its data keywords, where a quaternion starts in them). Each
# calls simlab's method of the same name, which 2.x code calls directly.
ROOT_WRITERS: dict[str, tuple[tuple[str, ...], int | None]] = {
    "write_root_pose_to_sim": (("root_pose",), 3),
    "write_root_link_pose_to_sim": (("root_pose",), 3),
    "write_root_velocity_to_sim": (("root_velocity",), None),
    "write_root_com_velocity_to_sim": (("root_velocity",), None),
    "write_root_link_velocity_to_sim": (("root_velocity",), None),
    "write_root_com_pose_to_sim": (("root_pose",), 3),
}

# mass properties of an articulation's or rigid object's bodies: (envs, bodies, ...) values
BODY_PROPERTY_WRITERS: dict[str, tuple[tuple[str, ...], int | None]] = {
    "set_masses": (("masses",), None),
    "set_coms": (("coms",), 3),
    "set_inertias": (("inertias",), None),
}

JOINT_WRITERS: dict[str, tuple[tuple[str, ...], int | None]] = {
    "write_joint_state_to_sim": (("position", "velocity"), None),
    "write_joint_position_to_sim": (("position",), None),
    "write_joint_velocity_to_sim": (("velocity",), None),
    "write_joint_stiffness_to_sim": (("stiffness",), None),
    "write_joint_damping_to_sim": (("damping",), None),
    "write_joint_position_limit_to_sim": (("limits",), None),
    "write_joint_velocity_limit_to_sim": (("limits",), None),
    "write_joint_effort_limit_to_sim": (("limits",), None),
    "write_joint_armature_to_sim": (("armature",), None),
    "write_joint_friction_coefficient_to_sim": (("joint_friction_coeff",), None),
    "set_joint_position_target": (("target",), None),
    "set_joint_velocity_target": (("target",), None),
    "set_joint_effort_target": (("target",), None),
}

# the rigid object collection's: its objects are 3.0's bodies, (envs, bodies, ...) values
BODY_WRITERS: dict[str, tuple[tuple[str, ...], int | None]] = {
    "write_body_pose_to_sim": (("body_poses",), 3),
    "write_body_link_pose_to_sim": (("body_poses",), 3),
    "write_body_com_pose_to_sim": (("body_poses",), 3),
    "write_body_velocity_to_sim": (("body_velocities",), None),
    "write_body_com_velocity_to_sim": (("body_velocities",), None),
    "write_body_link_velocity_to_sim": (("body_velocities",), None),
}


def _body_field(asset: Any, name: str) -> torch.Tensor:
    """(num_envs, num_bodies, ...) MjModel field ``name`` of the asset's bodies: each world's if the field
    was made per-world (randomized, written), else the compiled model's."""
    per_world = asset._physics.per_world_model_field(name)
    if per_world is not None:
        return per_world[:, asset._body_index.to(per_world.device)].to(asset.device, torch.float32)
    model = torch.as_tensor(getattr(asset._sim.model, name)[asset._body_ids], dtype=torch.float32, device=asset.device)
    return model.unsqueeze(0).expand(asset.num_instances, *model.shape)


class RootWriters:
    """Isaac Lab 3.0's root writers (``write_root_pose_to_sim_index`` / ``_mask``, ...), poses (x, y, z, w)."""

    def write_root_com_pose_to_sim(self, root_pose: torch.Tensor, env_ids: Any = None) -> None:
        """Place the root so that its centre of mass frame (its position, the principal axes' orientation)
        is ``root_pose`` (w, x, y, z), world frame: the root link's pose is written."""
        com_pos_b = _body_field(self, "body_ipos")[:, 0]
        com_quat_b = _body_field(self, "body_iquat")[:, 0]
        rows = slice(None) if env_ids is None else torch.as_tensor(env_ids, device=self.device)
        if isinstance(rows, torch.Tensor):  # a bool mask (the _mask writer) comes with a row per env
            rows = slice(None) if rows.dtype == torch.bool else rows.long()
        pos, quat = root_pose[:, :3], root_pose[:, 3:7]
        link_quat = math_utils.quat_mul(quat, math_utils.quat_inv(com_quat_b[rows]))
        link_pos = pos - math_utils.quat_apply(link_quat, com_pos_b[rows])
        self.write_root_link_pose_to_sim(torch.cat((link_pos, link_quat), dim=-1), env_ids)


class BodyPropertyWriters:
    """Isaac Lab 3.0's ``set_masses`` / ``set_coms`` / ``set_inertias`` (``_index`` / ``_mask``): the bodies'
    mass properties in each world (MuJoCo's per-world ``body_mass``, ``body_ipos``, ``body_iquat``,
    ``body_inertia``), then MuJoCo's derived constants (``set_const``) for the envs written."""

    def _write_bodies(self, field: str, values: torch.Tensor, body_ids: Any, env_ids: Any) -> torch.Tensor:
        physics = self._physics
        tensor = physics.model_field(field)
        envs = torch.arange(self.num_instances) if env_ids is None else torch.as_tensor(env_ids).cpu()
        values = torch.as_tensor(values, dtype=tensor.dtype, device=tensor.device)
        if envs.dtype == torch.bool:  # a mask (the _mask writers): full data, a row per env
            values, envs = values[envs.to(values.device)], envs.nonzero().flatten()
        envs = envs.long().flatten()
        local = torch.arange(self.num_bodies) if body_ids is None else torch.as_tensor(body_ids).long().flatten()
        bodies = self._body_index.cpu()[local]
        shape = (len(envs), len(bodies), *tensor.shape[2:])
        if values.shape != shape:
            raise ValueError(
                f"{field}: {len(envs)} envs x {len(bodies)} bodies take a tensor of shape {shape}, "
                f"got {tuple(values.shape)}"
            )
        envs, bodies = envs.to(tensor.device), bodies.to(tensor.device)
        tensor[envs[:, None], bodies] = values
        return envs

    def _after_mass_change(self, envs: torch.Tensor) -> None:
        with contextlib.suppress(NotImplementedError):  # the GPU backend keeps its derived constants
            self._physics.set_const(envs)

    def set_masses(self, masses: torch.Tensor, body_ids: Any = None, env_ids: Any = None) -> None:
        """Body masses [kg], (len(env_ids), len(body_ids))."""
        self._after_mass_change(self._write_bodies("body_mass", masses, body_ids, env_ids))

    def _keep_frames(self, field: str, values: torch.Tensor, body_ids: Any) -> None:
        """Refuse moving the centre of mass or turning the principal axes of a body that MuJoCo compiled with
        them on the body's frame (``body_sameframe``): its kinematics skip that frame, so it would be wrong."""
        model = self._sim.model
        local = range(self.num_bodies) if body_ids is None else torch.as_tensor(body_ids).flatten().tolist()
        identity = torch.tensor([0.0, 0.0, 0.0] if field == "body_ipos" else [1.0, 0.0, 0.0, 0.0])
        fixed = (1,) if field == "body_ipos" else (1, 3)  # mjSAMEFRAME_BODY, mjSAMEFRAME_BODYROT
        values = torch.as_tensor(values, dtype=torch.float32).cpu()
        for column, k in enumerate(local):
            body = int(self._body_ids[k])
            if model.body_sameframe[body] in fixed and not torch.allclose(values[:, column], identity, atol=1e-6):
                what = "centre of mass" if field == "body_ipos" else "principal axes of inertia"
                raise ValueError(
                    f"{model.body(body).name}: MuJoCo compiled this body with its {what} on the body's frame, which "
                    "its kinematics then skip; simlab cannot move them afterwards (masses and inertias about the "
                    "body's axes can be set)."
                )

    def set_coms(self, coms: torch.Tensor, body_ids: Any = None, env_ids: Any = None) -> None:
        """Centres of mass in each body's frame, (len(env_ids), len(body_ids), 3), or poses (..., 7) whose
        quaternion (w, x, y, z) orients the principal axes of inertia."""
        coms = torch.as_tensor(coms)
        self._keep_frames("body_ipos", coms[..., :3], body_ids)
        if coms.shape[-1] == 7:
            self._keep_frames("body_iquat", coms[..., 3:7], body_ids)
        envs = self._write_bodies("body_ipos", coms[..., :3], body_ids, env_ids)
        if coms.shape[-1] == 7:
            self._write_bodies("body_iquat", coms[..., 3:7], body_ids, env_ids)
        self._after_mass_change(envs)

    def set_inertias(self, inertias: torch.Tensor, body_ids: Any = None, env_ids: Any = None) -> None:
        """Inertia tensors about each body's centre of mass, (len(env_ids), len(body_ids), 9) row-major in the
        body frame (as 3.0 gives them): MuJoCo keeps their principal moments and axes."""
        matrix = torch.as_tensor(inertias, dtype=torch.float32).reshape(*torch.as_tensor(inertias).shape[:-1], 3, 3)
        moments, axes = torch.linalg.eigh(0.5 * (matrix + matrix.transpose(-1, -2)))
        axes = axes * torch.where(torch.linalg.det(axes) < 0, -1.0, 1.0)[..., None, None]  # a rotation
        iquat = math_utils.quat_unique(math_utils.quat_from_matrix(axes))
        diagonal = torch.diagonal(matrix, dim1=-2, dim2=-1)
        if torch.allclose(matrix, torch.diag_embed(diagonal), atol=1e-9):  # the body's axes are principal
            moments, iquat = diagonal, torch.tensor([1.0, 0.0, 0.0, 0.0]).expand(*diagonal.shape[:-1], 4)
        self._keep_frames("body_iquat", iquat, body_ids)
        envs = self._write_bodies("body_inertia", moments, body_ids, env_ids)
        self._write_bodies("body_iquat", iquat, body_ids, env_ids)
        self._after_mass_change(envs)


class JointWriters:
    """Isaac Lab 3.0's joint writers and target setters (``write_joint_position_to_sim_index`` / ``_mask``, ...)."""


class BodyWriters:
    """Isaac Lab 3.0's rigid object collection writers (``write_body_pose_to_sim_index`` / ``_mask``, ...)."""


_add_writers(RootWriters, ROOT_WRITERS, None)
_add_writers(BodyPropertyWriters, BODY_PROPERTY_WRITERS, "body")
_add_writers(BodyWriters, BODY_WRITERS, "body")
_add_writers(JointWriters, JOINT_WRITERS, "joint")


# -- actuators -------------------------------------------------------------------------------------


class TargetCommand:
    """Isaac Lab 3.0's ``robot.actuators.target_command``: the joint targets, set and read."""

    def __init__(self, articulation: Any):
        self._articulation = articulation

    position = property(lambda self: self._articulation.data.joint_pos_target)
    velocity = property(lambda self: self._articulation.data.joint_vel_target)
    effort = property(lambda self: self._articulation.data.joint_effort_target)


for _kind in ("position", "velocity", "effort"):
    for _select, _make in (("index", _index_writer), ("mask", _mask_writer)):
        _writer = _make(f"set_joint_{_kind}_target", ("value",), None, "joint")

        def _setter(self, _writer=_writer, **kwargs: Any) -> None:
            _writer(self._articulation, **kwargs)

        _setter.__name__ = f"set_{_kind}_{_select}"
        _setter.__doc__ = f"Isaac Lab 3.0's ``set_{_kind}_{_select}(*, value, ...)``: the joint {_kind} targets."
        setattr(TargetCommand, _setter.__name__, _setter)


class ActuatorCollection(dict):
    """Isaac Lab 3.0's ``Articulation.actuators``: the actuator groups by name (as in 2.x, a dict) with
    the command setters (``target_command``) and the effort telemetry of 3.0's collection."""

    def __init__(self, articulation: Any):
        super().__init__()
        self.target_command = TargetCommand(articulation)
        self._articulation = articulation

    @property
    def applied_effort(self) -> ProxyTensor:
        return self._articulation.data.applied_torque

    @property
    def computed_effort(self) -> ProxyTensor:
        return self._articulation.data.computed_torque
