"""Assets: articulations, rigid objects and collections of them, and the config of anything placed in a scene."""

from .articulation import Articulation, ArticulationData
from .articulation_cfg import ArticulationCfg
from .asset_base import AssetBase, AssetBaseCfg
from .deformable_object import DeformableObject, DeformableObjectCfg
from .rigid_object import RigidObject, RigidObjectCfg, RigidObjectData
from .rigid_object_collection import RigidObjectCollection, RigidObjectCollectionCfg, RigidObjectCollectionData
