"""Isaac Lab's asset converters (``isaaclab.sim.converters``): a URDF compiled by MuJoCo into MJCF."""

from .asset_converter_base_cfg import AssetConverterBaseCfg
from .urdf_converter import UrdfConverter
from .urdf_converter_cfg import UrdfConverterCfg

__all__ = ["AssetConverterBaseCfg", "UrdfConverter", "UrdfConverterCfg"]
