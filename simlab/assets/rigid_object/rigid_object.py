"""Rigid objects: one body, free (a free joint), kinematic (mocap) or static."""

from __future__ import annotations

from ..root_body import RootedAsset
from .rigid_object_data import RigidObjectData


class RigidObject(RootedAsset):
    """A single rigid body spawned from a shape or a file."""

    data: RigidObjectData

    def _make_data(self, sim) -> RigidObjectData:
        return RigidObjectData(self, sim)

    @property
    def num_bodies(self) -> int:
        return 1
