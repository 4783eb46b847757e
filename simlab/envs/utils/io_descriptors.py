"""IO descriptors of a manager-based env: what its policy reads and writes, in Isaac Lab's YAML layout.

``export_io_descriptors(env)`` writes ``<log_dir>/io_descriptors/IO_descriptors.yaml`` with

* ``observations``: per exported group (``policy``), one entry per term: ``name``, ``mdp_type``,
  ``full_path`` (the term function), ``shape``, ``dtype``, ``observation_type`` and, where the term
  reads an articulation, ``joint_names`` (and ``joint_pos_offsets`` / ``joint_vel_offsets`` for
  relative joint states); ``overloads`` (``scale``, ``clip``, ``history_length``,
  ``flatten_history_dim``) and ``extras`` (``description``, ``units``, ``modifiers``);
* ``actions``: one entry per action term: ``name``, ``mdp_type``, ``full_path``, ``shape``, ``dtype``,
  ``action_type``, ``joint_names``, ``scale``, ``offset``, ``clip`` and ``extras`` (``description``);
* ``articulations``: per articulation, its joint names and default joint state and properties;
* ``scene``: ``physics_dt``, ``dt`` (the env step) and ``decimation``.

Isaac Lab attaches these descriptions with decorators on its observation functions; simlab derives
them from the managers' terms (the observation types and units of simlab's own ``mdp`` functions are
listed here). Direct tasks compute observations in one method and have no terms to describe.
"""

from __future__ import annotations

import inspect
import os
import re
from typing import Any

import torch

__all__ = ["OBSERVATION_TYPES", "export_io_descriptors", "io_descriptors"]

OBSERVATION_TYPES: dict[str, tuple[str, str | None]] = {
    # function name: (observation_type, units)
    "base_pos_z": ("RootState", "m"),
    "base_lin_vel": ("RootState", "m/s"),
    "base_ang_vel": ("RootState", "rad/s"),
    "projected_gravity": ("RootState", "m/s^2"),
    "root_pos_w": ("RootState", "m"),
    "root_quat_w": ("RootState", "unit"),
    "root_lin_vel_w": ("RootState", "m/s"),
    "root_ang_vel_w": ("RootState", "rad/s"),
    "joint_pos": ("JointState", "rad"),
    "joint_pos_rel": ("JointState", "rad"),
    "joint_pos_limit_normalized": ("JointState", "normalized"),
    "joint_vel": ("JointState", "rad/s"),
    "joint_vel_rel": ("JointState", "rad/s"),
    "joint_effort": ("JointState", "N.m"),
    "last_action": ("Action", None),
    "generated_commands": ("Command", None),
}
"""Isaac Lab's observation types and units of simlab's ``mdp`` observation functions."""

_JOINT_OFFSETS = {
    "joint_pos_rel": ("joint_pos_offsets", "default_joint_pos"),
    "joint_vel_rel": ("joint_vel_offsets", "default_joint_vel"),
}


def io_descriptors(env: Any, groups: tuple[str, ...] = ("policy",)) -> dict[str, Any]:
    """The env's IO descriptors (plain lists and numbers, ready for YAML)."""
    if not hasattr(env, "observation_manager") or not hasattr(env, "action_manager"):
        raise TypeError(
            f"{type(env).__name__} has no observation and action managers: IO descriptors describe the terms of "
            "manager-based envs; direct tasks compute their observations in one method and have none."
        )
    return {
        "observations": _observation_descriptors(env, groups),
        "actions": _action_descriptors(env),
        "articulations": _articulation_data(env),
        "scene": {"physics_dt": env.physics_dt, "dt": env.step_dt, "decimation": env.cfg.decimation},
    }


def export_io_descriptors(env: Any, output_dir: str | None = None) -> str:
    """Write ``IO_descriptors.yaml`` into ``output_dir`` (default ``<cfg.log_dir>/io_descriptors``); returns
    its path."""
    import yaml

    if output_dir is None:
        if not getattr(env.cfg, "log_dir", None):
            raise ValueError(
                "Nowhere to write the IO descriptors: set env.cfg.log_dir (simlab train sets it to the run folder) "
                "or pass output_dir."
            )
        output_dir = os.path.join(env.cfg.log_dir, "io_descriptors")
    descriptors = io_descriptors(env)
    os.makedirs(output_dir, exist_ok=True)
    path = os.path.join(output_dir, "IO_descriptors.yaml")
    with open(path, "w") as f:
        yaml.safe_dump(descriptors, f, sort_keys=False)
    print(f"[INFO]: Exporting IO descriptors to {path}")
    return path


def _plain(value: Any) -> Any:
    """``value`` as YAML-safe lists, numbers and strings."""
    if isinstance(value, torch.Tensor):
        return value.detach().cpu().tolist()
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return repr(value)


def _description(obj: Any) -> str | None:
    doc = inspect.getdoc(obj)
    return " ".join(doc.split("\n\n")[0].split()) if doc else None


def _callable_name(func: Any) -> str:
    """A term function's name, or a class term's class name."""
    return func.__name__ if inspect.isfunction(func) else type(func).__name__


def _full_path(func: Any) -> str:
    target = func if inspect.isfunction(func) else type(func)
    return f"{target.__module__}.{target.__qualname__}"


def _observation_descriptors(env: Any, groups: tuple[str, ...]) -> dict[str, list[dict[str, Any]]]:
    manager = env.observation_manager
    out = {}
    for group, terms in manager._group_terms.items():
        if group not in groups:
            continue
        entries = []
        for (term_name, cfg), dim in zip(terms, manager.group_obs_term_dim[group]):
            func = cfg.func
            func_name = _callable_name(func)
            value = func(env, **cfg.params)
            observation_type, units = OBSERVATION_TYPES.get(func_name, (None, None))
            entry: dict[str, Any] = {
                "name": func_name,
                "overloads": {
                    "scale": _plain(cfg.scale),
                    "clip": _plain(cfg.clip),
                    "history_length": cfg.history_length,
                    "flatten_history_dim": cfg.flatten_history_dim,
                },
                "extras": {
                    "description": _description(func),
                    "units": units,
                    "modifiers": [_callable_name(m.func) for m in cfg.modifiers] if cfg.modifiers else None,
                },
                "mdp_type": "Observation",
                "term_name": term_name,
                "full_path": _full_path(func),
                "shape": list(dim),
                "dtype": str(value.dtype),
                "observation_type": observation_type,
            }
            asset_cfg = cfg.params.get("asset_cfg", _default_argument(func, "asset_cfg"))
            if asset_cfg is not None and observation_type == "JointState":
                asset = env.scene[asset_cfg.name]
                joint_ids = _ids(asset_cfg.joint_ids, asset.num_joints)
                entry["joint_names"] = [asset.joint_names[i] for i in joint_ids]
                if func_name in _JOINT_OFFSETS:
                    key, attribute = _JOINT_OFFSETS[func_name]
                    entry[key] = _plain(getattr(asset.data, attribute)[0, joint_ids])
            entries.append(entry)
        out[group] = entries
    return out


def _default_argument(func: Any, name: str) -> Any:
    """The default of ``func``'s parameter ``name`` (None if it has none)."""
    try:
        parameter = inspect.signature(func).parameters.get(name)
    except (TypeError, ValueError):
        return None
    return None if parameter is None or parameter.default is inspect.Parameter.empty else parameter.default


def _ids(ids: Any, count: int) -> list[int]:
    if ids is None or isinstance(ids, slice):
        return list(range(count))[ids or slice(None)]
    return [int(i) for i in ids]


def _action_descriptors(env: Any) -> list[dict[str, Any]]:
    entries = []
    for term_name, term in env.action_manager._terms.items():
        entry: dict[str, Any] = {
            "name": re.sub(r"([a-z])([A-Z])", r"\1_\2", type(term).__name__).lower(),
            "extras": {"description": _description(type(term))},
            "mdp_type": "Action",
            "term_name": term_name,
            "full_path": _full_path(term),
            "shape": [term.action_dim],
            "dtype": str(term.raw_actions.dtype),
        }
        joint_names = getattr(term, "_joint_names", None)
        if joint_names is not None:
            entry["action_type"] = "JointAction"
            entry["joint_names"] = list(joint_names)
            entry["scale"] = _first_env(getattr(term, "_scale", None))
            entry["offset"] = _first_env(getattr(term, "_offset", None))
            entry["clip"] = _first_env(getattr(term, "_clip", None))
        entries.append(entry)
    return entries


def _first_env(value: Any) -> Any:
    """A per-env tensor's first row (the terms keep (num_envs, ...) copies); numbers unchanged."""
    if isinstance(value, torch.Tensor) and value.dim() >= 2:
        value = value[0]
    return _plain(value)


def _articulation_data(env: Any) -> dict[str, dict[str, Any]]:
    out = {}
    for name, articulation in env.scene.articulations.items():
        data = articulation.data

        def first(attribute: str, fallback: str, data: Any = data) -> list:
            return _plain(getattr(data, attribute, getattr(data, fallback))[0])

        out[name] = {
            "joint_names": list(articulation.joint_names),
            "default_joint_pos": first("default_joint_pos", "default_joint_pos"),
            "default_joint_vel": first("default_joint_vel", "default_joint_vel"),
            "default_joint_pos_limits": first("default_joint_pos_limits", "joint_pos_limits"),
            "default_joint_damping": first("default_joint_damping", "joint_damping"),
            "default_joint_stiffness": first("default_joint_stiffness", "joint_stiffness"),
            "default_joint_friction": first("default_joint_friction", "joint_friction_coeff"),
            "default_joint_armature": first("default_joint_armature", "joint_armature"),
        }
    return out
