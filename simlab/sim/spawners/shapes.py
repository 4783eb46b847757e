"""Primitive shapes (box, sphere, capsule, cylinder, cone) as rigid bodies.

A shape is one body with one geom. It gets a free joint (a dynamic rigid object) unless
``rigid_props.kinematic_enabled`` makes it a mocap body, or no ``rigid_props`` are given at all,
in which case it is static, like a prim without rigid-body properties in Isaac Lab.
"""

from __future__ import annotations

import math
from dataclasses import MISSING

import mujoco

from simlab.utils import configclass

from ..simulation_context import current_spec
from .from_files import entity_name
from .materials import PreviewSurfaceCfg, RigidBodyMaterialCfg
from .spawner_cfg import RigidObjectSpawnerCfg


def spawn_shape(prim_path: str, cfg: ShapeCfg, translation=None, orientation=None) -> mujoco.MjsBody:
    spec = current_spec()
    name = entity_name(prim_path)
    body = spec.worldbody.add_body(
        name=f"{name}/body",
        pos=list(translation) if translation is not None else [0.0, 0.0, 0.0],
        quat=list(orientation) if orientation is not None else [1.0, 0.0, 0.0, 0.0],
    )
    rigid = cfg.rigid_props
    if rigid is not None and rigid.kinematic_enabled:
        body.mocap = True
    elif rigid is not None:
        body.add_freejoint(name=f"{name}/root")
        if rigid.disable_gravity:
            body.gravcomp = 1.0
    geom = body.add_geom(name=f"{name}/geom", type=cfg.geom_type(), size=cfg.geom_size())
    cfg.finish_geom(spec, geom, name)
    if cfg.visual_material is not None:
        geom.rgba = cfg.visual_material.rgba()
    if cfg.physics_material is not None:
        geom.friction = cfg.physics_material.friction()
    if cfg.collision_props is not None and cfg.collision_props.collision_enabled is False:
        geom.contype, geom.conaffinity = 0, 0
    if cfg.mass_props is not None and cfg.mass_props.mass is not None:
        geom.mass = cfg.mass_props.mass
    elif cfg.mass_props is not None and cfg.mass_props.density is not None:
        geom.density = cfg.mass_props.density
    return body


@configclass
class ShapeCfg(RigidObjectSpawnerCfg):
    func: object = spawn_shape
    visual_material: PreviewSurfaceCfg | None = None
    physics_material: RigidBodyMaterialCfg | None = None

    def geom_type(self) -> mujoco.mjtGeom:
        raise NotImplementedError

    def geom_size(self) -> list[float]:
        raise NotImplementedError

    def finish_geom(self, spec: mujoco.MjSpec, geom: mujoco.MjsGeom, name: str) -> None:
        """Shapes that MuJoCo has no primitive for add their mesh here."""


@configclass
class CuboidCfg(ShapeCfg):
    size: tuple[float, float, float] = MISSING
    """Full edge lengths (MuJoCo takes half-sizes)."""

    def geom_type(self):
        return mujoco.mjtGeom.mjGEOM_BOX

    def geom_size(self):
        return [s / 2 for s in self.size]


@configclass
class SphereCfg(ShapeCfg):
    radius: float = MISSING

    def geom_type(self):
        return mujoco.mjtGeom.mjGEOM_SPHERE

    def geom_size(self):
        return [self.radius, 0.0, 0.0]


@configclass
class CapsuleCfg(ShapeCfg):
    radius: float = MISSING
    height: float = MISSING
    """Length of the cylindrical part, along z."""
    axis: str = "Z"

    def geom_type(self):
        return mujoco.mjtGeom.mjGEOM_CAPSULE

    def geom_size(self):
        return [self.radius, self.height / 2, 0.0]


@configclass
class CylinderCfg(CapsuleCfg):
    def geom_type(self):
        return mujoco.mjtGeom.mjGEOM_CYLINDER


@configclass
class ConeCfg(ShapeCfg):
    """A cone along z, centred on its mid-height as Isaac Lab's (a convex mesh: MuJoCo has no cone)."""

    radius: float = MISSING
    height: float = MISSING
    axis: str = "Z"
    segments: int = 32
    """Edges of the base polygon."""

    def geom_type(self):
        return mujoco.mjtGeom.mjGEOM_MESH

    def geom_size(self):
        return [0.0, 0.0, 0.0]

    def finish_geom(self, spec, geom, name):
        if self.axis.upper() != "Z":
            raise ValueError(f"ConeCfg: only axis 'Z' is supported, got '{self.axis}'; rotate the prim instead.")
        angles = [2 * math.pi * k / self.segments for k in range(self.segments)]
        base = [[self.radius * math.cos(a), self.radius * math.sin(a), -self.height / 2] for a in angles]
        vertices = [coord for point in [*base, [0.0, 0.0, self.height / 2]] for coord in point]
        spec.add_mesh(name=f"{name}/cone", uservert=vertices)
        geom.meshname = f"{name}/cone"
