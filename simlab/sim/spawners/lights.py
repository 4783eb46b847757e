"""Lights. MuJoCo lights only matter for rendering; intensities map onto diffuse brightness.

Isaac Lab's (USD) light settings carry over: the brightness is ``intensity * 2**exposure``, and
``enable_color_temperature`` tints the colour with a black body's at ``color_temperature`` kelvin.
Dome and distant lights shine from above (a dome adds ambient light); a sphere or cylinder light is
a point light at its position, a disk light a spot light along its prim's -z axis.

A dome light that is ``visible_in_primary_ray`` (Isaac Lab's default) is also the sky a viewer sees:
MuJoCo's skybox, a gradient from the dome's colour overhead to a darker shade below. Videos and the
native viewer draw it; camera sensors do not (their renderers turn MuJoCo's skybox flag off, and MuJoCo
Warp's ray tracer draws none), so their images do not depend on it. A ``texture_file`` is not read:
the sky shows the dome's colour.
"""

from __future__ import annotations

import math
from typing import Literal

import mujoco
import numpy as np

from simlab.utils import configclass

from ..simulation_context import current_spec
from .spawner_cfg import SpawnerCfg


def _brightness(intensity: float) -> float:
    # Isaac Lab's typical dome/distant intensities are 1000-3000 (nits); MuJoCo takes 0-1.
    return float(min(1.0, max(0.05, intensity / 3000.0)))


def black_body_rgb(kelvin: float) -> tuple[float, float, float]:
    """The colour (0-1) of a black body at ``kelvin`` (1000-40000 K), by Tanner Helland's fit."""
    t = min(max(kelvin, 1000.0), 40000.0) / 100.0
    if t <= 66.0:
        red, green = 255.0, 99.4708025861 * math.log(t) - 161.1195681661
        blue = 0.0 if t <= 19.0 else 138.5177312231 * math.log(t - 10.0) - 305.0447927307
    else:
        red, green = 329.698727446 * (t - 60.0) ** -0.1332047592, 288.1221695283 * (t - 60.0) ** -0.0755148492
        blue = 255.0
    return tuple(min(max(c, 0.0), 255.0) / 255.0 for c in (red, green, blue))


SKY_HORIZON_SHADE = 0.4
"""The sky's colour below the horizon, as a share of its colour overhead."""
SKY_TEXTURE_WIDTH = 64
"""Pixels per side of each of the sky's six cube faces: a smooth gradient needs few."""


def add_sky(spec: mujoco.MjSpec, prim_path: str, color) -> None:
    """Give ``spec`` a skybox that fades from ``color`` overhead to a darker shade below, unless it has
    one (MuJoCo draws one skybox: the first dome light's)."""
    if any(texture.type == mujoco.mjtTexture.mjTEXTURE_SKYBOX for texture in spec.textures):
        return
    spec.add_texture(
        name=f"{prim_path.rstrip('/')}/sky",
        type=mujoco.mjtTexture.mjTEXTURE_SKYBOX,
        builtin=mujoco.mjtBuiltin.mjBUILTIN_GRADIENT,
        rgb1=[min(1.0, c) for c in color],
        rgb2=[min(1.0, c) * SKY_HORIZON_SHADE for c in color],
        width=SKY_TEXTURE_WIDTH,
        height=SKY_TEXTURE_WIDTH,
    )


def spawn_light(prim_path: str, cfg: LightCfg, translation=None, orientation=None):
    """Add the light to the spec being built."""
    spec = current_spec()
    color = cfg.color
    if cfg.enable_color_temperature:
        color = [c * t for c, t in zip(color, black_body_rgb(cfg.color_temperature))]
    diffuse = [c * _brightness(cfg.intensity * 2.0**cfg.exposure) for c in color]
    position = list(translation) if translation is not None else [0.0, 0.0, 10.0]
    kind, direction = mujoco.mjtLightType.mjLIGHT_DIRECTIONAL, [0.0, 0.0, -1.0]
    if isinstance(cfg, (SphereLightCfg, CylinderLightCfg)):
        kind = mujoco.mjtLightType.mjLIGHT_POINT
    elif isinstance(cfg, DiskLightCfg):
        kind = mujoco.mjtLightType.mjLIGHT_SPOT
        if orientation is not None:  # (w, x, y, z)
            quat = np.asarray(orientation, dtype=np.float64)
            rotated = np.zeros(3)
            mujoco.mju_rotVecQuat(rotated, np.array([0.0, 0.0, -1.0]), quat / np.linalg.norm(quat))
            direction = rotated.tolist()
    if isinstance(cfg, DomeLightCfg):
        # A dome light is light from everywhere: MuJoCo's headlight ambient term plus a top light.
        spec.visual.headlight.ambient = [0.4 * c for c in diffuse]
        if cfg.visible_in_primary_ray:
            add_sky(spec, prim_path, color)
    return spec.worldbody.add_light(
        name=prim_path.rstrip("/").split("/")[-1] or "light",
        type=kind,
        pos=position,
        dir=direction,
        diffuse=diffuse,
        castshadow=False,
    )


@configclass
class LightCfg(SpawnerCfg):
    func: object = spawn_light
    prim_type: str | None = None
    """USD's light type; the config class says which light it is here."""
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    enable_color_temperature: bool = False
    color_temperature: float = 6500.0
    """Kelvin; tints ``color`` when ``enable_color_temperature``."""
    normalize: bool = False
    """USD's: brightness independent of the light's size. MuJoCo lights have no size, so either holds."""
    exposure: float = 0.0
    """Brightness is ``intensity * 2**exposure``."""
    intensity: float = 1000.0


@configclass
class DomeLightCfg(LightCfg):
    prim_type: str | None = "DomeLight"
    texture_file: str | None = None
    texture_format: Literal["automatic", "latlong", "mirroredBall", "angular", "cubeMapVerticalCross"] = "automatic"
    visible_in_primary_ray: bool = True


@configclass
class DistantLightCfg(LightCfg):
    prim_type: str | None = "DistantLight"
    angle: float = 0.53


@configclass
class SphereLightCfg(LightCfg):
    prim_type: str | None = "SphereLight"
    radius: float = 0.5
    treat_as_point: bool = False


@configclass
class CylinderLightCfg(LightCfg):
    prim_type: str | None = "CylinderLight"
    length: float = 1.0
    radius: float = 0.5
    treat_as_line: bool = False


@configclass
class DiskLightCfg(LightCfg):
    prim_type: str | None = "DiskLight"
    radius: float = 0.5
