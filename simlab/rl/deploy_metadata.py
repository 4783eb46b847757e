"""What a robot-side runner needs beside the policy network, as ONNX metadata.

:func:`deploy_metadata` reads it from the env the policy was trained in: joint names in the
order of the action vector, default joint positions, the action terms' scale / offset / clip, the
PD gains of the actuators, the observation terms in the order the policy reads them (size, scale,
clip, history) and the time steps. Each value is a JSON string (ONNX metadata holds strings);
:func:`read_deploy_metadata` gives them back parsed. The keys are documented in ``docs/usage.md``
("Deploying an exported policy").

Manager-based envs describe all of it. A direct env maps actions to joints and builds observations
in its own methods, so only what its scene and config say is recorded (robot joints, defaults,
gains, time steps, sizes).
"""

from __future__ import annotations

import inspect
import json
import math
from typing import Any

import torch

import simlab

__all__ = ["METADATA_VERSION", "deploy_metadata", "read_deploy_metadata"]

METADATA_VERSION = 1
"""Bumped when a key changes meaning."""

# The action terms whose processed action is ``offset + scale * action`` per joint, and what it sets.
_JOINT_TARGETS = {
    "JointPositionAction": "position",
    "RelativeJointPositionAction": "position_delta",
    "JointVelocityAction": "velocity",
    "JointEffortAction": "effort",
}


def deploy_metadata(env: Any, task: str | None = None, obs_groups: list[str] | None = None) -> dict[str, str]:
    """The deploy metadata of ``env`` (wrapped or not) as ``{key: JSON string}``.

    ``obs_groups`` are the observation groups the policy reads, concatenated in this order
    (default ``["policy"]``).
    """
    base = env.unwrapped
    groups = list(obs_groups or ["policy"])
    meta: dict[str, Any] = {
        "simlab_metadata_version": METADATA_VERSION,
        "simlab_version": simlab.__version__,
        "task": task,
        "step_dt": float(base.step_dt),
        "physics_dt": float(base.physics_dt),
        "decimation": int(base.cfg.decimation),
        "observation_groups": groups,
    }
    if hasattr(base, "action_manager") and hasattr(base, "observation_manager"):
        meta["env_type"] = "manager_based"
        meta.update(_actions(base))
        meta.update(_observations(base, groups))
    else:
        meta["env_type"] = "direct"
        meta.update(_direct(base))
    meta["articulations"] = _articulations(base)
    return {key: json.dumps(value, allow_nan=False) for key, value in meta.items()}


def read_deploy_metadata(path: str) -> dict[str, Any]:
    """The parsed deploy metadata of an exported ONNX file (keys this module writes)."""
    import onnx

    model = onnx.load(path, load_external_data=False)
    return {p.key: json.loads(p.value) for p in model.metadata_props}


# -- actions ---------------------------------------------------------------------------------------


def _actions(env: Any) -> dict[str, Any]:
    """The action terms in the order of their slices of the action vector, and per-element arrays."""
    terms, names, default, scale, offset, clip, asset_joints = [], [], [], [], [], [], []
    all_joint_terms = True
    start = 0
    for name in env.action_manager.active_terms:
        term = env.action_manager.get_term(name)
        kind = type(term).__name__
        entry: dict[str, Any] = {"name": name, "type": kind, "slice": [start, start + term.action_dim]}
        entry["asset_name"] = getattr(term.cfg, "asset_name", None)
        target = next((t for cls, t in _JOINT_TARGETS.items() if _is(term, cls)), None)
        if target is None:
            all_joint_terms = False
            entry["params"] = _jsonable(_cfg_params(term.cfg))
            entry["deploy"] = f"unsupported for deploy: {kind} is not offset + scale * action on joints"
        else:
            asset = env.scene[term.cfg.asset_name]
            joints = list(term.joint_names)
            ids = [asset.joint_names.index(j) for j in joints]
            entry.update(
                target=target,
                joint_names=joints,
                scale=_per_joint(term._scale, len(joints)),
                offset=_per_joint(term._offset, len(joints)),
                clip=_clip(term._clip, len(joints)),
                use_default_offset=getattr(term.cfg, "use_default_offset", None),
                deploy="supported",
            )
            names += joints
            default += _row(asset.data.default_joint_pos[0, ids])
            scale += entry["scale"]
            offset += entry["offset"]
            clip += entry["clip"]
            asset_joints += [(asset, j) for j in joints]
        terms.append(entry)
        start += term.action_dim
    out: dict[str, Any] = {"action_terms": terms, "action_size": start}
    if all_joint_terms:  # one number per action element: what a runner applies
        out.update(
            joint_names=names,
            default_joint_pos=default,
            action_scale=scale,
            action_offset=offset,
            action_clip=clip,
            **_gains(asset_joints),
        )
    return out


def _is(term: Any, class_name: str) -> bool:
    return any(cls.__name__ == class_name for cls in type(term).__mro__)


def _cfg_params(cfg: Any) -> dict[str, Any]:
    d = cfg.to_dict() if hasattr(cfg, "to_dict") else dict(vars(cfg))
    return {k: v for k, v in d.items() if k not in ("class_type", "debug_vis")}


def _per_joint(value: Any, n: int) -> list[float]:
    """A term's scale or offset (a float, or per env and joint) as one value per joint (env 0's)."""
    if isinstance(value, torch.Tensor):
        return _row(value[0] if value.dim() > 1 else value.expand(n))
    return [float(value)] * n


def _clip(value: torch.Tensor | None, n: int) -> list[list[float | None] | None]:
    """Per joint ``[low, high]`` (``None`` for an unbounded side), or ``None`` without a clip."""
    if value is None:
        return [None] * n
    return [[_finite(lo), _finite(hi)] for lo, hi in value[0].tolist()]


def _gains(asset_joints: list[tuple[Any, str]]) -> dict[str, list]:
    """Per joint: the actuator group and model, stiffness, damping, effort and velocity limits (env 0's);
    None for a joint no actuator drives."""
    out: dict[str, list] = {k: [] for k in ("joint_actuator", "joint_stiffness", "joint_damping")}
    out.update(joint_effort_limit=[], joint_velocity_limit=[], joint_armature=[])
    for asset, joint in asset_joints:
        found = next(((g, a) for g, a in asset.actuators.items() if joint in a.joint_names), None)
        if found is None:  # a passive joint (the Shadow hand's coupled distal joints): no drive, no gains
            for values in out.values():
                values.append(None)
            continue
        group, actuator = found
        k = actuator.joint_names.index(joint)
        out["joint_actuator"].append(group)
        out["joint_stiffness"].append(_at(actuator.stiffness, k))
        out["joint_damping"].append(_at(actuator.damping, k))
        effort = min(_at(actuator.effort_limit, k), _at(actuator.effort_limit_sim, k))
        out["joint_effort_limit"].append(_finite(effort))
        out["joint_velocity_limit"].append(_finite(_at(actuator.velocity_limit_sim, k)))
        out["joint_armature"].append(_at(actuator.armature, k))
    return out


def _at(value: torch.Tensor | float, k: int) -> float:
    if isinstance(value, torch.Tensor):
        return float(value[0, k] if value.dim() > 1 else value[k] if value.dim() == 1 else value)
    return float(value)


# -- observations ----------------------------------------------------------------------------------


def _observations(env: Any, groups: list[str]) -> dict[str, Any]:
    """The terms of ``groups`` in the order the policy's input concatenates them."""
    manager = env.observation_manager
    unknown = [g for g in groups if g not in manager.active_terms]
    if unknown:
        raise ValueError(f"No observation group {unknown}; the env's groups: {list(manager.active_terms)}")
    terms, start = [], 0
    for group in groups:
        for name, shape in zip(manager.active_terms[group], manager.group_obs_term_dim[group]):
            cfg = manager.get_term_cfg(group, name)
            size = math.prod(shape)
            func = cfg.func if not hasattr(cfg.func, "__func__") else cfg.func.__func__
            terms.append(
                {
                    "group": group,
                    "name": name,
                    "function": getattr(func, "__name__", type(func).__name__),
                    "slice": [start, start + size],
                    "shape": list(shape),
                    "scale": _jsonable(cfg.scale),
                    "clip": _jsonable(cfg.clip),
                    "history_length": cfg.history_length,
                    "params": _jsonable(_term_params(env, cfg.func, cfg.params)),
                }
            )
            start += size
    return {"observation_names": [t["name"] for t in terms], "observation_terms": terms, "observation_size": start}


def _term_params(env: Any, func: Any, params: dict[str, Any]) -> dict[str, Any]:
    """A term's arguments, defaults included; a scene entity becomes its name and the joints or
    bodies it selects (none selected: all of the articulation's, see ``articulations``)."""
    target = func if inspect.isfunction(func) or inspect.ismethod(func) else type(func).__call__
    defaults = {
        k: p.default
        for k, p in inspect.signature(target).parameters.items()
        if p.default is not inspect.Parameter.empty
    }
    out = {}
    for key, value in {**defaults, **params}.items():
        if hasattr(value, "joint_ids") and getattr(value, "name", None) in env.scene:
            asset = env.scene[value.name]
            entity: dict[str, Any] = {"name": value.name}
            if value.joint_names is not None and hasattr(asset, "joint_names"):
                entity["joint_names"] = [asset.joint_names[i] for i in _ids(value.joint_ids, asset.num_joints)]
            if value.body_names is not None and hasattr(asset, "body_names"):
                entity["body_names"] = [asset.body_names[i] for i in _ids(value.body_ids, asset.num_bodies)]
            value = entity
        out[key] = value
    return out


def _ids(ids: Any, count: int) -> list[int]:
    return list(range(count)) if isinstance(ids, slice) else [int(i) for i in ids]


# -- direct envs -----------------------------------------------------------------------------------


def _direct(env: Any) -> dict[str, Any]:
    """What a direct env's config says; its action mapping lives in its own code."""
    return {
        "action_size": _space_size(getattr(env.cfg, "action_space", None)),
        "observation_size": _space_size(getattr(env.cfg, "observation_space", None)),
        "action_terms": "unsupported for deploy: a direct task maps actions to joints in its own _apply_action",
        "observation_terms": "unsupported for deploy: a direct task builds its observation in _get_observations",
    }


def _articulations(env: Any) -> dict[str, Any]:
    """Each articulation's joints in its own order (a term that selects no joints reads all, in this
    order), default joint positions, per-joint gains and its actuator groups with their configs."""
    out = {}
    for name, asset in env.scene.articulations.items():
        joints = list(asset.joint_names)
        actuators = {
            group: {
                "type": type(a).__name__,
                "joint_names": list(a.joint_names),
                "cfg": _jsonable(_cfg_params(a.cfg)),
            }
            for group, a in asset.actuators.items()
        }
        out[name] = {
            "joint_names": joints,
            "default_joint_pos": _row(asset.data.default_joint_pos[0]),
            **_gains([(asset, j) for j in joints]),
            "actuators": actuators,
        }
    return out


def _space_size(space: Any) -> int | None:
    if isinstance(space, int):
        return space
    if isinstance(space, (list, tuple)) and all(isinstance(s, int) for s in space):
        return math.prod(space)
    return None


# -- JSON ------------------------------------------------------------------------------------------


def _row(t: torch.Tensor) -> list[float]:
    return [float(v) for v in t.detach().cpu().flatten().tolist()]


def _finite(v: float) -> float | None:
    return float(v) if math.isfinite(v) else None


def _jsonable(value: Any) -> Any:
    """Plain JSON: tensors become lists, infinities ``None``, anything else its ``repr``."""
    if isinstance(value, torch.Tensor):
        return _jsonable(value.detach().cpu().tolist())
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, float):
        return _finite(value)
    if value is None or isinstance(value, (bool, int, str)):
        return value
    return repr(value)
