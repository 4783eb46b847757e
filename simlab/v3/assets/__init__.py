"""``isaaclab.assets`` of Isaac Lab 3.0: simlab's assets with ``init_state.rot`` in (x, y, z, w) order.

The configs are simlab's (:mod:`simlab.assets`) with one difference: their ``InitialStateCfg`` holds
``rot`` as Isaac Lab 3.0 writes it, ``(x, y, z, w)``, identity ``(0, 0, 0, 1)``, and checks it when
made (:func:`simlab.v3._order.check_xyzw_rot`). The asset classes convert their config to simlab's
order when they are built (:func:`simlab.v3._order.to_simlab`); so do :mod:`simlab.v3.scene` and
:mod:`simlab.v3.envs` for the configs they hold.
"""

from __future__ import annotations

from simlab import assets as _assets
from simlab.assets import (
    ArticulationData,
    AssetBase,
    DeformableObject,
    DeformableObjectCfg,
    RigidObjectCollection,
    RigidObjectCollectionCfg,
    RigidObjectCollectionData,
    RigidObjectData,
)
from simlab.utils import configclass
from simlab.v3._order import to_simlab, xyzw_class

__all__ = [
    "Articulation",
    "ArticulationCfg",
    "ArticulationData",
    "AssetBase",
    "AssetBaseCfg",
    "DeformableObject",
    "DeformableObjectCfg",
    "RigidObject",
    "RigidObjectCfg",
    "RigidObjectCollection",
    "RigidObjectCollectionCfg",
    "RigidObjectCollectionData",
    "RigidObjectData",
]


class Articulation(_assets.Articulation):
    """simlab's articulation, made from a config whose quaternions are (x, y, z, w)."""

    def __init__(self, cfg: _assets.ArticulationCfg):
        super().__init__(to_simlab(cfg))


class RigidObject(_assets.RigidObject):
    """simlab's rigid object, made from a config whose quaternions are (x, y, z, w)."""

    def __init__(self, cfg: _assets.RigidObjectCfg):
        super().__init__(to_simlab(cfg))


@configclass
class AssetBaseCfg(_assets.AssetBaseCfg):
    InitialStateCfg = xyzw_class(_assets.AssetBaseCfg.InitialStateCfg, __name__)
    init_state: InitialStateCfg = InitialStateCfg()


@configclass
class ArticulationCfg(_assets.ArticulationCfg):
    InitialStateCfg = xyzw_class(_assets.ArticulationCfg.InitialStateCfg, __name__)
    class_type: type = Articulation
    init_state: InitialStateCfg = InitialStateCfg()


@configclass
class RigidObjectCfg(_assets.RigidObjectCfg):
    InitialStateCfg = xyzw_class(_assets.RigidObjectCfg.InitialStateCfg, __name__)
    class_type: type = RigidObject
    init_state: InitialStateCfg = InitialStateCfg()
