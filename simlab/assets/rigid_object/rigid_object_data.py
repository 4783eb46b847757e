"""The data of a rigid object (Isaac Lab's ``isaaclab.assets.rigid_object.rigid_object_data``)."""

from __future__ import annotations

from ..root_body import RootedAssetData


class RigidObjectData(RootedAssetData):
    """Root state and body views of a rigid object (see ``RootedAssetData``)."""
