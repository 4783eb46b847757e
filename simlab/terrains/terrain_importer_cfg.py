"""Configuration of the terrain importer: what ground the scene stands on."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.sim.spawners.materials import MdlFileCfg, PreviewSurfaceCfg, RigidBodyMaterialCfg
from simlab.utils import configclass

from .terrain_generator_cfg import TerrainGeneratorCfg
from .terrain_importer import TerrainImporter


@configclass
class TerrainImporterCfg:
    class_type: type = TerrainImporter
    collision_group: int = -1
    prim_path: str = MISSING
    """Name of the terrain in the model (e.g. "/World/ground")."""
    num_envs: int = 1
    """Set by the scene from its own ``num_envs``."""
    terrain_type: str = "generator"
    """"plane" (an infinite ground plane, envs on a grid ``env_spacing`` apart) or "generator"
    (tiles from ``terrain_generator``, envs on the tiles)."""
    terrain_generator: TerrainGeneratorCfg | None = None
    usd_path: str | None = None
    env_spacing: float | None = None
    """Grid spacing of the env origins for a plane; set by the scene from its own ``env_spacing``."""
    visual_material: PreviewSurfaceCfg | MdlFileCfg | None = None
    """Colour of the terrain (with the generator's ``color_scheme`` "none")."""
    physics_material: RigidBodyMaterialCfg = RigidBodyMaterialCfg()
    use_terrain_origins: bool = True
    """Place envs on the tiles' origins (False: on a grid ``env_spacing`` apart, over the tiles)."""
    max_init_terrain_level: int | None = None
    """Highest row (difficulty level) an env starts on; None: any row."""
    debug_vis: bool = False
