"""IO descriptors: what a trained policy reads and writes, for whoever deploys it.

A manager-based env describes its policy's inputs and outputs from its own managers: each
observation term of the exported groups (name, where its function lives, what it computes, shape,
dtype, scale / clip / history, joint or body names), each action term (type, shape, joints, scale,
offset, clip), the scene's articulations (joint names, defaults, limits, gains) and the time steps.
``env.export_IO_descriptors(dir)`` writes it as ``IO_descriptors.yaml``, Isaac Lab's file name and
layout; ``--export_io_descriptors`` on ``train`` writes it into the run folder. Direct envs compute
their observations in one method, so they have no terms to describe.

Every term is described; :func:`generic_io_descriptor` only adds to the description (Isaac Lab's
decorator: extra fields and ``on_inspect`` hooks that read the term's output and arguments). It
marks the function and returns it unchanged, so a decorated term costs nothing in the step.
"""

from __future__ import annotations

import dataclasses
import inspect
import os
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import torch
import yaml

from simlab.utils import configclass
from simlab.utils.io import write_text

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv

__all__ = [
    "GenericActionIODescriptor",
    "GenericObservationIODescriptor",
    "action_io_descriptors",
    "export_articulations_data",
    "export_io_descriptors",
    "export_scene_data",
    "generic_io_descriptor",
    "io_descriptors",
    "observation_io_descriptors",
    "record_body_names",
    "record_dtype",
    "record_joint_names",
    "record_joint_pos_offsets",
    "record_joint_vel_offsets",
    "record_shape",
]

FILE_NAME = "IO_descriptors.yaml"


@configclass
class GenericObservationIODescriptor:
    """One observation term, as written to the YAML file."""

    mdp_type: str = "Observation"
    name: str | None = None
    full_path: str | None = None
    description: str | None = None
    shape: tuple[int, ...] | None = None
    dtype: str | None = None
    observation_type: str | None = None
    extras: dict[str, Any] = {}


@configclass
class GenericActionIODescriptor:
    """One action term, as written to the YAML file."""

    mdp_type: str = "Action"
    name: str | None = None
    full_path: str | None = None
    description: str | None = None
    shape: tuple[int, ...] | None = None
    dtype: str | None = None
    action_type: str | None = None
    extras: dict[str, Any] = {}
    export: bool = True


_OBS_FIELDS = {f.name for f in dataclasses.fields(GenericObservationIODescriptor)}


def generic_io_descriptor(_func: Callable | None = None, *, on_inspect=None, **fields: Any):
    """Mark an observation function with fields for its descriptor (Isaac Lab's decorator).

    ``fields`` that are descriptor fields (``observation_type``, ``description``, ...) set them; any
    other (``units="rad"``) goes to ``extras``. ``on_inspect`` hooks are called when descriptors are
    exported, as ``hook(output=..., descriptor=..., env=..., **the term's arguments)``.
    """
    hooks = [on_inspect] if callable(on_inspect) else list(on_inspect or [])

    def mark(func: Callable) -> Callable:
        func._io_descriptor_fields = dict(fields)
        func._io_descriptor_hooks = hooks
        func._has_descriptor = True
        return func

    if isinstance(_func, GenericObservationIODescriptor):  # @generic_io_descriptor(Descriptor(...))
        fields = {k: v for k, v in dataclasses.asdict(_func).items() if v is not None and k != "extras"}
        fields.update(_func.extras)
        return mark
    return mark(_func) if callable(_func) else mark


# -- hooks (Isaac Lab's names) ---------------------------------------------------------------------


def record_shape(output: torch.Tensor, descriptor, **kwargs) -> None:
    descriptor.shape = (output.shape[-1],)


def record_dtype(output: torch.Tensor, descriptor, **kwargs) -> None:
    descriptor.dtype = str(output.dtype)


def _selected(ids, count: int) -> list[int]:
    return list(range(count)) if isinstance(ids, slice) else [int(i) for i in ids]


def record_joint_names(output: torch.Tensor, descriptor, env, asset_cfg, **kwargs) -> None:
    asset = env.scene[asset_cfg.name]
    descriptor.joint_names = [asset.joint_names[i] for i in _selected(asset_cfg.joint_ids, asset.num_joints)]


def record_body_names(output: torch.Tensor, descriptor, env, asset_cfg, **kwargs) -> None:
    asset = env.scene[asset_cfg.name]
    descriptor.body_names = [asset.body_names[i] for i in _selected(asset_cfg.body_ids, asset.num_bodies)]


def record_joint_pos_offsets(output: torch.Tensor, descriptor, env, asset_cfg, **kwargs) -> None:
    """The default joint positions the term subtracts (of env 0: every env shares the robot)."""
    descriptor.joint_pos_offsets = env.scene[asset_cfg.name].data.default_joint_pos[0, asset_cfg.joint_ids]


def record_joint_vel_offsets(output: torch.Tensor, descriptor, env, asset_cfg, **kwargs) -> None:
    descriptor.joint_vel_offsets = env.scene[asset_cfg.name].data.default_joint_vel[0, asset_cfg.joint_ids]


# -- building the descriptors ----------------------------------------------------------------------


def _plain(value: Any) -> Any:
    """YAML-safe: tensors and tuples become lists, numbers stay numbers."""
    if isinstance(value, torch.Tensor):
        return value.detach().cpu().tolist()
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return repr(value)


def _doc(obj: Any) -> str | None:
    doc = inspect.getdoc(obj)
    return " ".join(doc.split()) if doc else None


def _func_name(func: Any) -> tuple[str, str]:
    """(name, full path) of a term's function or class instance."""
    target = func if inspect.isfunction(func) or inspect.isclass(func) else type(func)
    return target.__name__, f"{target.__module__}.{target.__qualname__}"


def _arguments(func: Any, env: ManagerBasedEnv, params: dict[str, Any]) -> dict[str, Any]:
    """The term's arguments by name, its defaults included (what the hooks are given)."""
    target = func.__call__ if not (inspect.isfunction(func) or inspect.ismethod(func)) else func
    bound = inspect.signature(target).bind(env, **params)
    bound.apply_defaults()
    return dict(bound.arguments)


def _asset_names(env: ManagerBasedEnv, params: dict[str, Any]) -> dict[str, Any]:
    """Joint / body names a term reads, from its ``asset_cfg`` (when it selects some)."""
    asset_cfg = params.get("asset_cfg")
    if asset_cfg is None or getattr(asset_cfg, "name", None) not in env.scene:
        return {}
    asset = env.scene[asset_cfg.name]
    out: dict[str, Any] = {}
    if getattr(asset_cfg, "joint_names", None) is not None and hasattr(asset, "joint_names"):
        out["joint_names"] = [asset.joint_names[i] for i in _selected(asset_cfg.joint_ids, asset.num_joints)]
    if getattr(asset_cfg, "body_names", None) is not None and hasattr(asset, "body_names"):
        out["body_names"] = [asset.body_names[i] for i in _selected(asset_cfg.body_ids, asset.num_bodies)]
    return out


def observation_io_descriptors(env: ManagerBasedEnv, groups: list[str] | None = None) -> dict[str, list[dict]]:
    """Per observation group (default: ``policy``), one entry per term in the group's order."""
    manager = env.observation_manager
    groups = ["policy"] if groups is None else groups
    unknown = [g for g in groups if g not in manager.active_terms]
    if unknown:
        raise ValueError(f"No observation group {unknown}; groups: {list(manager.active_terms)}")
    out: dict[str, list[dict]] = {}
    for group in groups:
        entries = []
        for name, shape in zip(manager.active_terms[group], manager.group_obs_term_dim[group]):
            cfg = manager.get_term_cfg(group, name)
            func_name, full_path = _func_name(cfg.func)
            output = cfg.func(env, **cfg.params)
            args = _arguments(cfg.func, env, cfg.params)
            desc = GenericObservationIODescriptor(
                name=name, full_path=full_path, description=_doc(cfg.func), dtype=str(output.dtype)
            )
            desc.extras = {"function": func_name, **_asset_names(env, args)}
            for key, value in getattr(cfg.func, "_io_descriptor_fields", {}).items():
                if key in _OBS_FIELDS:
                    setattr(desc, key, value)
                else:
                    desc.extras[key] = value
            for hook in getattr(cfg.func, "_io_descriptor_hooks", []):
                hook(output=output, descriptor=desc, **args)
            desc.shape = tuple(shape)  # after the hooks: the shape the policy sees (history included)
            entry = {k: v for k, v in vars(desc).items() if k != "extras"}
            entry["name"] = name
            entry["overloads"] = {
                "scale": cfg.scale,
                "clip": cfg.clip,
                "noise": type(cfg.noise).__name__ if cfg.noise is not None else None,
                "history_length": cfg.history_length,
                "flatten_history_dim": cfg.flatten_history_dim,
            }
            entry["extras"] = desc.extras
            entries.append(_plain(entry))
        out[group] = entries
    return out


def action_io_descriptors(env: ManagerBasedEnv) -> list[dict]:
    """One entry per action term, in the order their slices make up the action vector."""
    entries = []
    for name in env.action_manager.active_terms:
        term = env.action_manager.get_term(name)
        desc = term.IO_descriptor
        desc.name = name
        entry = {k: v for k, v in vars(desc).items() if k not in ("extras", "export")}
        entry.update(desc.extras)
        entries.append(_plain(entry))
    return entries


def export_articulations_data(env: ManagerBasedEnv) -> dict[str, dict[str, Any]]:
    """Joint names and the defaults of env 0 (every env holds the same robot) per articulation."""
    out = {}
    for name, articulation in env.scene.articulations.items():
        data = articulation.data
        fields = {"joint_names": list(articulation.joint_names)}
        for field in (
            "default_joint_pos",
            "default_joint_vel",
            "default_joint_pos_limits",
            "default_joint_damping",
            "default_joint_stiffness",
            "default_joint_friction",
            "default_joint_armature",
        ):
            value = getattr(data, field, None)
            if value is not None:
                fields[field] = value[0]
        out[name] = _plain(fields)
    return out


def export_scene_data(env: ManagerBasedEnv) -> dict[str, Any]:
    return {"physics_dt": env.physics_dt, "dt": env.step_dt, "decimation": env.cfg.decimation}


def io_descriptors(env: ManagerBasedEnv, groups: list[str] | None = None) -> dict[str, Any]:
    return {
        "observations": observation_io_descriptors(env, groups),
        "actions": action_io_descriptors(env),
        "articulations": export_articulations_data(env),
        "scene": export_scene_data(env),
    }


def export_io_descriptors(env: ManagerBasedEnv, output_dir: str) -> str:
    """Write ``IO_descriptors.yaml`` into ``output_dir``; returns its path."""
    os.makedirs(output_dir, exist_ok=True)
    path = os.path.join(output_dir, FILE_NAME)
    write_text(path, yaml.safe_dump(io_descriptors(env), sort_keys=False))
    return path
