"""Isaac Lab's mesh shapes (``MeshCuboidCfg``, ...): the same solids as the primitive shapes.

Isaac Lab spawns these as triangle meshes so that they can also be deformable bodies. simlab
simulates rigid bodies only: a mesh shape spawns as its primitive (a box, a sphere, ...), and one
given ``deformable_props`` or a deformable material is refused, saying what to use.
"""

from __future__ import annotations

from typing import Any

from simlab.utils import configclass
from simlab.utils.errors import ConfigError

from .shapes import CapsuleCfg, ConeCfg, CuboidCfg, CylinderCfg, SphereCfg, spawn_shape


@configclass
class DeformableBodyPropertiesCfg:
    """Isaac Lab's (PhysX) deformable-body settings, its fields and defaults: accepted as a config (so that
    its configs build and meet the one-line refusal), refused when spawned."""

    deformable_enabled: bool | None = None
    kinematic_enabled: bool = False
    self_collision: bool | None = None
    self_collision_filter_distance: float | None = None
    settling_threshold: float | None = None
    sleep_damping: float | None = None
    sleep_threshold: float | None = None
    solver_position_iteration_count: int | None = None
    vertex_velocity_damping: float | None = None
    simulation_hexahedral_resolution: int = 10
    collision_simplification: bool = True
    collision_simplification_remeshing: bool = True
    collision_simplification_remeshing_resolution: int = 0
    collision_simplification_target_triangle_count: int = 0
    collision_simplification_force_conforming: bool = True
    contact_offset: float | None = None
    rest_offset: float | None = None
    max_depenetration_velocity: float | None = None


@configclass
class DeformableBodyMaterialCfg:
    """Isaac Lab's deformable material: accepted as a config, refused when spawned."""

    density: float | None = None
    dynamic_friction: float = 0.25
    youngs_modulus: float = 50000000.0
    poissons_ratio: float = 0.45
    elasticity_damping: float = 0.005
    damping_scale: float = 1.0


def spawn_mesh_shape(prim_path: str, cfg: Any, translation=None, orientation=None):
    if cfg.deformable_props is not None or isinstance(cfg.physics_material, DeformableBodyMaterialCfg):
        raise ConfigError(
            f"'{prim_path}': {type(cfg).__name__} with deformable_props / a deformable material asks for a PhysX"
            " deformable body, which simlab (MuJoCo rigid bodies) does not simulate. Leave deformable_props=None"
            " for a rigid mesh shape, or use the primitive configs (CuboidCfg, SphereCfg, ...)."
        )
    return spawn_shape(prim_path, cfg, translation, orientation)


def _mesh_variant(base: type, doc: str) -> type:
    @configclass
    class MeshShape(base):
        func: object = spawn_mesh_shape
        deformable_props: DeformableBodyPropertiesCfg | None = None
        physics_material: Any = None

    MeshShape.__name__ = MeshShape.__qualname__ = f"Mesh{base.__name__}"
    MeshShape.__doc__ = doc
    return MeshShape


MeshCuboidCfg = _mesh_variant(CuboidCfg, "A box (Isaac Lab's mesh cuboid), rigid in simlab.")
MeshSphereCfg = _mesh_variant(SphereCfg, "A sphere (Isaac Lab's mesh sphere), rigid in simlab.")
MeshCapsuleCfg = _mesh_variant(CapsuleCfg, "A capsule (Isaac Lab's mesh capsule), rigid in simlab.")
MeshCylinderCfg = _mesh_variant(CylinderCfg, "A cylinder (Isaac Lab's mesh cylinder), rigid in simlab.")
MeshConeCfg = _mesh_variant(ConeCfg, "A cone (Isaac Lab's mesh cone), rigid in simlab.")
