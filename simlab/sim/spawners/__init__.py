"""Spawners: configs whose ``func(prim_path, cfg)`` adds a ground, light, robot or shape to the spec."""

from ..schemas import (
    ArticulationRootPropertiesCfg,
    CollisionPropertiesCfg,
    FixedTendonPropertiesCfg,
    JointDrivePropertiesCfg,
    MassPropertiesCfg,
    RigidBodyPropertiesCfg,
)
from .from_files import (
    GroundPlaneCfg,
    MjcfFileCfg,
    UrdfFileCfg,
    UsdFileCfg,
    entity_name,
    spawn_from_mjcf,
    spawn_from_urdf,
    spawn_from_usd,
    spawn_ground_plane,
)
from .lights import (
    CylinderLightCfg,
    DiskLightCfg,
    DistantLightCfg,
    DomeLightCfg,
    LightCfg,
    SphereLightCfg,
    spawn_light,
)
from .materials import MdlFileCfg, PreviewSurfaceCfg, RigidBodyMaterialCfg
from .meshes import (
    DeformableBodyMaterialCfg,
    DeformableBodyPropertiesCfg,
    MeshCapsuleCfg,
    MeshConeCfg,
    MeshCuboidCfg,
    MeshCylinderCfg,
    MeshSphereCfg,
)
from .sensors import PinholeCameraCfg, spawn_camera
from .shapes import CapsuleCfg, ConeCfg, CuboidCfg, CylinderCfg, ShapeCfg, SphereCfg, spawn_shape
from .spawner_cfg import RigidObjectSpawnerCfg, SpawnerCfg
