"""Rigid objects: one body, free (a free joint), kinematic (mocap) or static."""

from __future__ import annotations

from simlab.utils import configclass

from .asset_base import AssetBaseCfg
from .root_body import RootedAsset, RootedAssetData


class RigidObjectData(RootedAssetData):
    """Root state and body views of a rigid object (see ``RootedAssetData``)."""


class RigidObject(RootedAsset):
    """A single rigid body spawned from a shape or a file."""

    data: RigidObjectData

    def _make_data(self, sim) -> RigidObjectData:
        return RigidObjectData(self, sim)

    @property
    def num_bodies(self) -> int:
        return 1


@configclass
class RigidObjectCfg(AssetBaseCfg):
    @configclass
    class InitialStateCfg(AssetBaseCfg.InitialStateCfg):
        lin_vel: tuple[float, float, float] = (0.0, 0.0, 0.0)
        ang_vel: tuple[float, float, float] = (0.0, 0.0, 0.0)

    class_type: type = RigidObject
    init_state: InitialStateCfg = InitialStateCfg()
