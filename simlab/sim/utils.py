"""Isaac Lab's prim and stage helpers (``isaaclab.sim.utils``) on simlab's stage, a MuJoCo ``MjSpec``.

simlab's "stage" is the spec of the current :class:`SimulationContext`: spawners add bodies, geoms
and lights to it, named ``<Name>/...`` after the last element of their prim path, until
``sim.reset()`` compiles it. The helpers that make sense for that model work here:

- :func:`get_current_stage`, :func:`create_new_stage`, :func:`clear_stage`, :func:`update_stage`,
  :func:`get_stage_up_axis`;
- :func:`create_prim` for ``Xform`` groups (a namespace such as ``/World/Objects``; other prim types
  are spawned with the spawner configs) and :func:`is_prim_path_valid`.

The others query or edit USD itself (layers, schemas, materials bound by path, variants, labels,
xform ops); they exist so that ported code imports, and raise an error saying what to use instead.
"""

from __future__ import annotations

import re
import weakref
from collections.abc import Sequence
from typing import Any

import mujoco

from .simulation_context import SimulationContext

__all__ = [
    "clear_stage",
    "create_new_stage",
    "create_prim",
    "get_current_stage",
    "get_stage_up_axis",
    "is_prim_path_valid",
    "update_stage",
    "xform_group_origins",
    "xform_groups",
]


def _sim_for_stage() -> SimulationContext:
    sim = SimulationContext.instance()
    if sim is None:
        raise RuntimeError(
            "No stage: simlab's stage is the MjSpec of the current SimulationContext. Create one first, e.g."
            " sim = sim_utils.SimulationContext(sim_utils.SimulationCfg())."
        )
    return sim


def get_current_stage() -> mujoco.MjSpec:
    """The ``MjSpec`` that spawners are adding to (the current simulation's)."""
    return _sim_for_stage().spec


def create_new_stage() -> None:
    """Drop the current simulation (closing its physics), so the next ``SimulationContext`` starts empty."""
    SimulationContext.clear_instance()


def clear_stage() -> None:
    """Remove everything spawned so far: the current simulation gets an empty spec (before ``sim.reset()``)."""
    sim = _sim_for_stage()
    if sim.model is not None:
        raise RuntimeError("The simulation is already compiled; clear the stage before sim.reset().")
    sim.spec = sim._new_spec()
    _xform_paths(sim).clear()


def update_stage() -> None:
    """Isaac Lab flushes pending USD edits to the renderer here; spec edits apply at once, so nothing is pending."""


def get_stage_up_axis() -> str:
    """``"Z"``: MuJoCo worlds are z-up."""
    return "Z"


# Xform groups defined with create_prim, per simulation, in creation order, with their translation
# (they leave no trace in the spec itself)
_XFORM_PATHS: weakref.WeakKeyDictionary[SimulationContext, dict[str, tuple[float, float, float]]] = (
    weakref.WeakKeyDictionary()
)


def _xform_paths(sim: SimulationContext) -> dict[str, tuple[float, float, float]]:
    return _XFORM_PATHS.setdefault(sim, {})


def xform_group_origins(prim_path: str) -> list[tuple[float, float, float]] | None:
    """The translations of the ``Xform`` groups the parent of ``prim_path`` matches, in creation order.

    Isaac Lab's ``/World/Origin.*/Robot`` spawns one robot under each ``/World/Origin<i>`` group;
    in simlab each match becomes one world with the group's translation as its env origin. None
    when the parent names no group made with :func:`create_prim`.
    """
    sim = SimulationContext.instance()
    parent = prim_path.rstrip("/").rpartition("/")[0]
    if sim is None or not parent:
        return None
    groups = _xform_paths(sim)
    try:
        matches = [t for path, t in groups.items() if re.fullmatch(parent, path)]
    except re.error:
        return None
    return matches or None


def xform_groups(pattern: str) -> dict[str, tuple[float, float, float]]:
    """The ``Xform`` groups made with :func:`create_prim` whose whole path the regex ``pattern``
    matches (``/World/Origin_.*/CameraSensor``), with their translations, in creation order."""
    sim = SimulationContext.instance()
    if sim is None:
        return {}
    try:
        compiled = re.compile(pattern.rstrip("/"))
    except re.error:
        return {}
    return {path: t for path, t in _xform_paths(sim).items() if compiled.fullmatch(path)}


def path_below_xform_group(prim_path: str) -> str | None:
    """The part of ``prim_path`` below the ``Xform`` groups its leading part matches (made with
    :func:`create_prim`): ``/World/Origin.*/ball/body`` -> ``ball/body``, as the per-group asset
    ``/World/Origin.*/ball`` is named in the model. None when no leading part names a group."""
    sim = SimulationContext.instance()
    if sim is None or not _xform_paths(sim):
        return None
    parts = prim_path.rstrip("/").split("/")
    for cut in range(len(parts) - 1, 1, -1):  # the longest leading part first
        try:
            pattern = re.compile("/".join(parts[:cut]))
        except re.error:
            continue
        if any(pattern.fullmatch(path) for path in _xform_paths(sim)):
            return "/".join(parts[cut:])
    return None


def create_prim(
    prim_path: str,
    prim_type: str = "Xform",
    position: Sequence[float] | None = None,
    translation: Sequence[float] | None = None,
    orientation: Sequence[float] | None = None,
    scale: Sequence[float] | None = None,
    usd_path: str | None = None,
    semantic_label: str | None = None,
    semantic_type: str = "class",
    attributes: dict[str, Any] | None = None,
) -> str:
    """Define an ``Xform`` group at ``prim_path`` (a namespace for the entities spawned under it).

    A ``translation`` (or ``position``) places the group: an asset whose prim path matches several
    groups (``/World/Origin.*/Robot``) gets one world per group, offset by that translation (see
    :func:`xform_group_origins`). A rotated or scaled group, a USD file or attributes are refused
    rather than ignored. Returns ``prim_path``.
    """
    if prim_type != "Xform":
        raise NotImplementedError(
            f"create_prim('{prim_path}', '{prim_type}'): simlab spawns geometry from configs, not USD prim types."
            " Use e.g. sim_utils.CuboidCfg(size=...).func(prim_path, cfg) or sim_utils.MjcfFileCfg(asset_path=...)."
        )
    identity = orientation is None or tuple(orientation) == (1.0, 0.0, 0.0, 0.0)
    given = {"orientation": None if identity else orientation, "scale": None if scale in (None, (1, 1, 1)) else scale}
    given |= {"usd_path": usd_path, "semantic_label": semantic_label, "attributes": attributes}
    refused = [k for k, v in given.items() if v is not None]
    if refused:
        raise NotImplementedError(
            f"create_prim('{prim_path}', 'Xform', {', '.join(refused)}=...): an Xform group in simlab carries a"
            " translation only; give rotations to the spawner of each entity (func(prim_path, cfg, orientation=...))."
        )
    if not prim_path.startswith("/"):
        raise ValueError(f"Prim paths are absolute, e.g. '/World/Objects'; got '{prim_path}'.")
    offset = translation if translation is not None else position
    offset = tuple(float(x) for x in offset) if offset is not None else (0.0, 0.0, 0.0)
    if len(offset) != 3:
        raise ValueError(f"create_prim('{prim_path}'): translation is (x, y, z), got {offset}.")
    _xform_paths(_sim_for_stage())[prim_path.rstrip("/")] = offset
    return prim_path


def is_prim_path_valid(prim_path: str) -> bool:
    """Whether ``prim_path`` names an ``Xform`` group or an entity spawned into the current stage."""
    sim = _sim_for_stage()
    path = prim_path.rstrip("/")
    if path in _xform_paths(sim) or any(p.startswith(path + "/") for p in _xform_paths(sim)):
        return True
    name = path.split("/")[-1]
    spec = sim.spec
    elements = [*spec.bodies, *spec.geoms, *spec.lights, *spec.sites]
    return any(e.name == name or e.name.startswith(f"{name}/") for e in elements if e.name)


# -- USD-only helpers: the names exist, and say what to use ----------------------------------------

_USE_SPAWNERS = "spawn with the configs in simlab.sim (MjcfFileCfg, UrdfFileCfg, CuboidCfg, GroundPlaneCfg, ...)"
_USE_SPEC = "edit the MjSpec from sim_utils.get_current_stage() (mujoco.MjSpec API) before sim.reset()"
_USE_ASSET = "read poses from the asset's data (e.g. robot.data.root_pos_w, body_pos_w) after sim.reset()"

_USD_ONLY: dict[str, str] = {
    "add_reference_to_stage": _USE_SPAWNERS,
    "traverse_stage": _USE_SPEC,
    "get_prim_at_path": _USE_SPEC,
    "get_prim_path": _USE_SPEC,
    "define_prim": "use create_prim(path, 'Xform') for groups, or " + _USE_SPAWNERS,
    "get_prim_type_name": _USE_SPEC,
    "get_next_free_path": "pick a unique entity name (the last element of the prim path)",
    "create_fixed_root_joint": "set ArticulationRootPropertiesCfg(fix_root_link=True) on the spawner",
    "delete_prim": _USE_SPEC + " (spec.delete(element))",
    "make_uninstanceable": "nothing to do: MjSpec elements are never instanced",
    "set_prim_visibility": "set the geom's rgba alpha or group in the MjSpec",
    "safe_set_attribute_on_usd_schema": _USE_SPEC,
    "safe_set_attribute_on_usd_prim": _USE_SPEC,
    "change_prim_property": _USE_SPEC,
    "export_prim_to_file": "write the MjSpec with spec.to_xml()",
    "apply_nested": _USE_SPEC,
    "clone": "set InteractiveSceneCfg(num_envs=...): every world shares one compiled model",
    "bind_visual_material": "give the spawner cfg a visual_material (PreviewSurfaceCfg)",
    "bind_physics_material": "give the spawner cfg a physics_material (RigidBodyMaterialCfg)",
    "add_usd_reference": _USE_SPAWNERS,
    "get_usd_references": _USE_SPEC,
    "select_usd_variants": "write one MJCF per variant and point MjcfFileCfg at it",
    "get_next_free_prim_path": "pick a unique entity name (the last element of the prim path)",
    "get_first_matching_ancestor_prim": _USE_SPEC,
    "get_first_matching_child_prim": _USE_SPEC,
    "get_all_matching_child_prims": _USE_SPEC,
    "find_first_matching_prim": _USE_SPEC,
    "find_matching_prims": _USE_SPEC,
    "matches_path_expr_prefix": _USE_SPEC,
    "resolve_matching_prims_from_source": _USE_SPEC,
    "find_matching_prim_paths": "use the asset's find_bodies/find_joints (regexes over names) after sim.reset()",
    "find_global_fixed_joint_prim": "check the articulation's is_fixed_base after sim.reset()",
    "add_labels": "semantic labels are a USD/Replicator feature; simlab renders RGB and depth only",
    "get_labels": "semantic labels are a USD/Replicator feature; simlab renders RGB and depth only",
    "remove_labels": "semantic labels are a USD/Replicator feature; simlab renders RGB and depth only",
    "check_missing_labels": "semantic labels are a USD/Replicator feature; simlab renders RGB and depth only",
    "count_total_labels": "semantic labels are a USD/Replicator feature; simlab renders RGB and depth only",
    "resolve_paths": "asset paths are plain local file paths in simlab",
    "is_current_stage_in_memory": "the MjSpec always lives in memory",
    "open_stage": "load an MJCF with sim_utils.MjcfFileCfg(asset_path=...)",
    "use_stage": _USE_SPEC,
    "save_stage": "write the MjSpec with sim_utils.get_current_stage().to_xml()",
    "close_stage": "create_new_stage() or SimulationContext.clear_instance()",
    "get_current_stage_id": "get_current_stage() returns the MjSpec itself",
    "standardize_xform_ops": "poses are set by the spawners' translation/orientation",
    "validate_standard_xform_ops": "poses are set by the spawners' translation/orientation",
    "resolve_prim_pose": _USE_ASSET,
    "resolve_prim_scale": "MuJoCo geoms carry their size in the spec (geom.size)",
    "convert_world_pose_to_local": "use simlab.utils.math.subtract_frame_transforms",
}


def _usd_only(name: str, instead: str):
    def helper(*args: Any, **kwargs: Any) -> Any:
        raise NotImplementedError(
            f"sim_utils.{name} works on USD prims; simlab's stage is a MuJoCo MjSpec with no USD. Instead: {instead}."
        )

    helper.__name__ = helper.__qualname__ = name
    helper.__doc__ = f"USD-only in Isaac Lab; raises in simlab. Instead: {instead}."
    return helper


for _name, _instead in _USD_ONLY.items():
    globals()[_name] = _usd_only(_name, _instead)
__all__ += sorted(_USD_ONLY)
