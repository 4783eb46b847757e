"""The config of a rigid object (Isaac Lab's ``isaaclab.assets.rigid_object.rigid_object_cfg``)."""

from __future__ import annotations

from simlab.utils import configclass

from ..asset_base import AssetBaseCfg
from .rigid_object import RigidObject


@configclass
class RigidObjectCfg(AssetBaseCfg):
    @configclass
    class InitialStateCfg(AssetBaseCfg.InitialStateCfg):
        lin_vel: tuple[float, float, float] = (0.0, 0.0, 0.0)
        ang_vel: tuple[float, float, float] = (0.0, 0.0, 0.0)

    class_type: type = RigidObject
    init_state: InitialStateCfg = InitialStateCfg()
