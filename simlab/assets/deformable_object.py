"""Isaac Lab's deformable objects: the names exist so that configs which mention them import
(``object: RigidObjectCfg | DeformableObjectCfg``); making one is refused, saying what to use."""

from __future__ import annotations

from simlab.utils import configclass
from simlab.utils.errors import ConfigError

from .asset_base import AssetBaseCfg

_WHY = (
    "simlab simulates rigid bodies and articulations; Isaac Lab's deformable objects are PhysX soft bodies. "
    "Use RigidObjectCfg with a rigid spawner (sim_utils.CuboidCfg, MeshCuboidCfg, MjcfFileCfg, ...)."
)


class DeformableObject:
    def __init__(self, cfg: DeformableObjectCfg):
        raise ConfigError(f"DeformableObject('{cfg.prim_path}'): {_WHY}")


@configclass
class DeformableObjectCfg(AssetBaseCfg):
    class_type: type = DeformableObject

    def __post_init__(self):
        raise ConfigError(f"DeformableObjectCfg: {_WHY}")
