"""Isaac Lab 3.0's asset API on simlab's assets: its data view, its ``_index`` / ``_mask`` writers and
its actuator command collection, all mapped onto simlab's 2.x methods.

The same asset serves 2.x code and 3.0 code: the data fields are simlab's tensors ``(w, x, y, z)``
with 3.0's ``.torch`` ``(x, y, z, w)`` on them (:mod:`simlab.v3._proxy`), and the 3.0 names
(``write_root_pose_to_sim_index``, ``actuators.target_command``, ``data.default_root_pose``) exist
only in 3.0's spelling, so every value they take or give is converted at this boundary, once.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import torch

from simlab.v3._proxy import ProxyTensor, as_v3, proxy

__all__ = ["ActuatorCollection", "AssetDataView", "BodyWriters", "JointWriters", "RootWriters", "TargetCommand"]


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


class RootWriters:
    """Isaac Lab 3.0's root writers (``write_root_pose_to_sim_index`` / ``_mask``, ...), poses (x, y, z, w)."""


class JointWriters:
    """Isaac Lab 3.0's joint writers and target setters (``write_joint_position_to_sim_index`` / ``_mask``, ...)."""


class BodyWriters:
    """Isaac Lab 3.0's rigid object collection writers (``write_body_pose_to_sim_index`` / ``_mask``, ...)."""


_add_writers(RootWriters, ROOT_WRITERS, None)
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
