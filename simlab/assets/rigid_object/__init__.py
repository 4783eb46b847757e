"""Rigid objects, laid out as Isaac Lab's ``isaaclab.assets.rigid_object`` package."""

from .rigid_object import RigidObject
from .rigid_object_cfg import RigidObjectCfg
from .rigid_object_data import RigidObjectData

__all__ = ["RigidObject", "RigidObjectCfg", "RigidObjectData"]
