"""Visual materials: the colours of geoms."""

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
