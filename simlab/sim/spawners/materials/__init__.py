"""Visual and physics materials of geoms; Isaac Lab's layout (``visual_materials_cfg``, ``physics_materials_cfg``)."""

from .physics_materials_cfg import RigidBodyMaterialCfg
from .visual_materials_cfg import MdlFileCfg, PreviewSurfaceCfg
