"""The config of a rigid object collection (Isaac Lab's ``rigid_object_collection_cfg``)."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.utils import configclass

from ..rigid_object import RigidObjectCfg
from .rigid_object_collection import RigidObjectCollection


@configclass
class RigidObjectCollectionCfg:
    """Several rigid objects handled as one asset: their data has an object axis, ``(num_envs, num_objects, ...)``."""

    class_type: type = RigidObjectCollection
    rigid_objects: dict[str, RigidObjectCfg] = MISSING
    """Name -> config of each object (the objects' order is this dict's)."""
