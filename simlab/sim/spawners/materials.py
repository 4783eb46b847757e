"""Visual and physics materials: colours and friction of geoms."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.utils import configclass


@configclass
class PreviewSurfaceCfg:
    diffuse_color: tuple[float, float, float] = (0.18, 0.18, 0.18)
    emissive_color: tuple[float, float, float] = (0.0, 0.0, 0.0)
    roughness: float = 0.5
    metallic: float = 0.0
    opacity: float = 1.0

    def rgba(self) -> list[float]:
        return [*self.diffuse_color, self.opacity]


@configclass
class MdlFileCfg:
    """Isaac Lab's material from an MDL shader file (e.g. the terrain's marble tiles). MuJoCo cannot
    read MDL, so geoms given one are drawn in the plain ``fallback_color``."""

    mdl_path: str = MISSING
    project_uvw: bool | None = None
    albedo_brightness: float | None = None
    texture_scale: tuple[float, float] | None = None
    fallback_color: tuple[float, float, float] = (0.55, 0.55, 0.5)

    def rgba(self) -> list[float]:
        return [*self.fallback_color, 1.0]


@configclass
class RigidBodyMaterialCfg:
    """MuJoCo has one sliding friction per geom: ``static_friction`` sets it."""

    static_friction: float = 0.5
    dynamic_friction: float = 0.5
    restitution: float = 0.0
    friction_combine_mode: str = "average"
    restitution_combine_mode: str = "average"
    compliant_contact_stiffness: float = 0.0
    compliant_contact_damping: float = 0.0

    def friction(self) -> list[float]:
        return [self.static_friction, 0.005, 0.0001]
