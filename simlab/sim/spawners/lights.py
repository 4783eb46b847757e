"""Lights. MuJoCo lights only matter for rendering; intensities map onto diffuse brightness."""

from __future__ import annotations

import mujoco

from simlab.utils import configclass

from ..simulation_context import current_spec
from .spawner_cfg import SpawnerCfg


def _brightness(intensity: float) -> float:
    # Isaac Lab's typical dome/distant intensities are 1000-3000 (nits); MuJoCo takes 0-1.
    return float(min(1.0, max(0.05, intensity / 3000.0)))


def spawn_light(prim_path: str, cfg: LightCfg, translation=None, orientation=None):
    """Add a directional light (dome or distant) to the spec being built."""
    spec = current_spec()
    diffuse = [c * _brightness(cfg.intensity) for c in cfg.color]
    if isinstance(cfg, DomeLightCfg):
        # A dome light is light from everywhere: MuJoCo's headlight ambient term plus a top light.
        spec.visual.headlight.ambient = [0.4 * c for c in diffuse]
    light = spec.worldbody.add_light(
        name=prim_path.rstrip("/").split("/")[-1] or "light",
        type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL,
        pos=list(translation) if translation is not None else [0.0, 0.0, 10.0],
        dir=[0.0, 0.0, -1.0],
        diffuse=diffuse,
        castshadow=False,
    )
    return light


@configclass
class LightCfg(SpawnerCfg):
    func: object = spawn_light
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    intensity: float = 1000.0


@configclass
class DomeLightCfg(LightCfg):
    texture_file: str | None = None


@configclass
class DistantLightCfg(LightCfg):
    angle: float = 0.53
