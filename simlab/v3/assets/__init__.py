"""``isaaclab.assets`` of Isaac Lab 3.0: simlab's assets with ``init_state.rot`` in (x, y, z, w) order.

The configs are simlab's (:mod:`simlab.assets`) with one difference: their ``InitialStateCfg`` holds
``rot`` as Isaac Lab 3.0 writes it, ``(x, y, z, w)``, identity ``(0, 0, 0, 1)``, and checks it when
made (:func:`simlab.v3._order.check_xyzw_rot`). The asset classes convert their config to simlab's
order when they are built (:func:`simlab.v3._order.to_simlab`); so do :mod:`simlab.v3.scene` and
:mod:`simlab.v3.envs` for the configs they hold.

The asset classes also carry Isaac Lab 3.0's asset API (:mod:`simlab.v3.assets._api`): data fields
with ``.torch`` (quaternions ``(x, y, z, w)``), ``default_root_pose`` / ``default_root_vel``, the
``write_*_to_sim_index`` / ``_mask`` writers and ``actuators.target_command``. A scene or env of
:mod:`simlab.v3` builds its articulations and rigid objects as these classes, 2.x robot configs
included (:func:`simlab.v3.scene.with_v3_api`); 2.x code reading the same assets still gets ``(w, x, y, z)``.
"""

from __future__ import annotations

from simlab import assets as _assets
from simlab.assets import (
    ArticulationData,
    AssetBase,
    DeformableObject,
    DeformableObjectCfg,
    RigidObjectCollectionCfg,
    RigidObjectCollectionData,
    RigidObjectData,
)
from simlab.utils import configclass
from simlab.v3._order import to_simlab, xyzw_class
from simlab.v3._proxy import proxy
from simlab.v3.assets._api import (
    ActuatorCollection,
    AssetDataView,
    BodyPropertyWriters,
    BodyWriters,
    JointWriters,
    RootWriters,
)

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


class Articulation(JointWriters, RootWriters, BodyPropertyWriters, _assets.Articulation):
    """simlab's articulation, made from a config whose quaternions are (x, y, z, w), with Isaac Lab 3.0's API."""

    def __init__(self, cfg: _assets.ArticulationCfg):
        super().__init__(to_simlab(cfg))
        self.actuators = ActuatorCollection(self)  # filled with the groups when the sim starts, as simlab's dict

    def _initialize(self, sim) -> None:
        super()._initialize(sim)
        self.data = ArticulationDataView(self.data, self)

    @property
    def num_base_dofs(self) -> int:
        """Isaac Lab 3.0's floating-base columns of the Jacobian: 0 for a fixed base, 6 for a floating one."""
        return 0 if self.is_fixed_base else 6


class ArticulationDataView(AssetDataView):
    """An articulation's data as Isaac Lab 3.0 reads it, with ``body_link_jacobian_w``: the bodies'
    Jacobians in the world frame, laid out as 2.x's ``root_physx_view.get_jacobians()`` (a fixed base's
    root body left out; ``num_base_dofs`` floating-base columns before the joints')."""

    __slots__ = ("_asset",)

    def __init__(self, data, asset) -> None:
        super().__init__(data)
        object.__setattr__(self, "_asset", asset)

    def __getattr__(self, name: str):
        if name == "body_link_jacobian_w":
            return proxy(name, object.__getattribute__(self, "_asset").root_physx_view.get_jacobians())
        return super().__getattr__(name)

    def __dir__(self) -> list[str]:
        return sorted({*super().__dir__(), "body_link_jacobian_w"})


class RigidObject(RootWriters, BodyPropertyWriters, _assets.RigidObject):
    """simlab's rigid object, made from a config whose quaternions are (x, y, z, w), with Isaac Lab 3.0's API."""

    def __init__(self, cfg: _assets.RigidObjectCfg):
        super().__init__(to_simlab(cfg))

    def _initialize(self, sim) -> None:
        super()._initialize(sim)
        self.data = AssetDataView(self.data)


class RigidObjectCollection(BodyWriters, _assets.RigidObjectCollection):
    """simlab's rigid object collection, made from a config whose quaternions are (x, y, z, w), with Isaac
    Lab 3.0's API (its objects are 3.0's bodies: ``write_body_pose_to_sim_index``, ``data.body_pose_w.torch``)."""

    def __init__(self, cfg: _assets.RigidObjectCollectionCfg):
        super().__init__(to_simlab(cfg))

    def _initialize(self, sim) -> None:
        super()._initialize(sim)
        self.data = AssetDataView(self.data)


# simlab's asset class -> the class with Isaac Lab 3.0's API that a 3.0 scene builds instead (simlab.v3.scene)
V3_CLASSES: dict[type, type] = {
    _assets.Articulation: Articulation,
    _assets.RigidObject: RigidObject,
    _assets.RigidObjectCollection: RigidObjectCollection,
}


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
