"""Physics schema configs of spawned assets, at Isaac Lab's import path (``isaaclab.sim.schemas``)."""

from .schemas_cfg import (
    ArticulationRootPropertiesCfg,
    CollisionPropertiesCfg,
    FixedTendonPropertiesCfg,
    JointDrivePropertiesCfg,
    MassPropertiesCfg,
    RigidBodyPropertiesCfg,
)
