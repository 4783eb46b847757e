"""Terrains with Isaac Lab's names: the importer, the tile generator and its sub-terrains."""

from .box_terrains import (
    MeshInvertedPyramidStairsTerrainCfg,
    MeshPlaneTerrainCfg,
    MeshPyramidStairsTerrainCfg,
    MeshRandomGridTerrainCfg,
)
from .config import FLAT_TERRAINS_CFG, ROUGH_TERRAINS_CFG
from .flat_patches import FlatPatchSamplingCfg, find_flat_patches
from .height_field import (
    HfInvertedPyramidSlopedTerrainCfg,
    HfPyramidSlopedTerrainCfg,
    HfRandomUniformTerrainCfg,
    HfTerrainBaseCfg,
)
from .sub_terrain_cfg import SubTerrainBaseCfg, TileGeometry
from .terrain_generator import TerrainGenerator, generate_terrain
from .terrain_generator_cfg import TerrainGeneratorCfg
from .terrain_importer import TerrainImporter
from .terrain_importer_cfg import TerrainImporterCfg

__all__ = [
    "FLAT_TERRAINS_CFG",
    "FlatPatchSamplingCfg",
    "ROUGH_TERRAINS_CFG",
    "HfInvertedPyramidSlopedTerrainCfg",
    "HfPyramidSlopedTerrainCfg",
    "HfRandomUniformTerrainCfg",
    "HfTerrainBaseCfg",
    "MeshInvertedPyramidStairsTerrainCfg",
    "MeshPlaneTerrainCfg",
    "MeshPyramidStairsTerrainCfg",
    "MeshRandomGridTerrainCfg",
    "SubTerrainBaseCfg",
    "TerrainGenerator",
    "TerrainGeneratorCfg",
    "TerrainImporter",
    "TerrainImporterCfg",
    "TileGeometry",
    "find_flat_patches",
    "generate_terrain",
]
