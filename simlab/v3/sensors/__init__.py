"""``isaaclab.sensors`` of Isaac Lab 3.0: simlab's sensors with ``offset.rot`` in (x, y, z, w) order.

The sensor configs are simlab's (:mod:`simlab.sensors`) with their offsets holding ``rot`` as Isaac
Lab 3.0 writes it. A scene or env of :mod:`simlab.v3` converts them to simlab's order when it is
built (simlab's own scene refuses them, since its sensors read (w, x, y, z)). The other names are
:mod:`simlab.sensors`'s.

The sensor classes here are simlab's with Isaac Lab 3.0's data access: ``sensor.data.<field>.torch``
(quaternions ``(x, y, z, w)``), the contact sensor's 3.0 names (``net_normal_forces_w``, ...) and
``compute_first_contact(dt).torch``. A scene or env of :mod:`simlab.v3` builds its sensors as these
(:func:`simlab.v3.scene.with_v3_api`); 2.x code reading the same sensors still gets simlab's tensors.
"""

from __future__ import annotations

from typing import Any

import simlab.sensors as _sensors
from simlab.sensors.frame_transformer.frame_transformer_cfg import OffsetCfg as _FrameOffsetCfg
from simlab.utils import configclass
from simlab.v3._order import xyzw_class
from simlab.v3._proxy import proxy
from simlab.v3.assets._api import AssetDataView

__all__ = [
    "Camera",
    "CameraCfg",
    "ContactSensor",
    "FrameTransformer",
    "FrameTransformerCfg",
    "Imu",
    "ImuCfg",
    "JointWrenchSensor",
    "OffsetCfg",
    "RayCaster",
    "RayCasterCfg",
    "TiledCamera",
    "TiledCameraCfg",
]


def _no_friction_split(data: Any) -> None:
    raise AttributeError(
        "friction_force_matrix_w: simlab's contact sensor does not split friction from normal forces; "
        "force_matrix_w (3.0's normal_force_matrix_w here) holds each partner's whole contact force."
    )


class SensorDataView(AssetDataView):
    """A sensor's data as Isaac Lab 3.0 reads it (``.torch`` on every tensor), with the contact
    sensor's force names of 3.0 (its migration guide: "Contact force property names"). MuJoCo's
    contact sensors sum whole contact forces (normal and friction): 3.0's ``normal`` names read those."""

    __slots__ = ()
    renamed = {
        "net_normal_forces_w": lambda d: d.net_forces_w,
        "net_normal_forces_w_history": lambda d: d.net_forces_w_history,
        "normal_force_matrix_w": lambda d: d.force_matrix_w,
        "normal_force_matrix_w_history": lambda d: d.force_matrix_w_history,
        "friction_force_matrix_w": _no_friction_split,
    }


def _with_v3_data(cls: type) -> type:
    """``cls`` (a simlab sensor) whose ``data`` and contact-time methods give what 3.0 code reads."""
    namespace: dict[str, Any] = {
        "__module__": __name__,
        "__qualname__": cls.__name__,
        "__doc__": f"simlab's ``{cls.__name__}`` with Isaac Lab 3.0's data access (``.torch``, 3.0's names).",
        "data": property(lambda self: SensorDataView(cls.data.fget(self))),
    }
    for method in ("compute_first_contact", "compute_first_air"):
        if hasattr(cls, method):
            base = getattr(cls, method)
            namespace[method] = lambda self, dt, abs_tol=1.0e-8, _base=base: proxy("first", _base(self, dt, abs_tol))
    return type(cls.__name__, (cls,), namespace)


Camera = _with_v3_data(_sensors.Camera)
ContactSensor = _with_v3_data(_sensors.ContactSensor)
FrameTransformer = _with_v3_data(_sensors.FrameTransformer)
Imu = _with_v3_data(_sensors.Imu)
JointWrenchSensor = _with_v3_data(_sensors.JointWrenchSensor)
RayCaster = _with_v3_data(_sensors.RayCaster)
TiledCamera = _with_v3_data(_sensors.TiledCamera)

V3_CLASSES: dict[type, type] = {
    _sensors.Camera: Camera,
    _sensors.ContactSensor: ContactSensor,
    _sensors.FrameTransformer: FrameTransformer,
    _sensors.Imu: Imu,
    _sensors.JointWrenchSensor: JointWrenchSensor,
    _sensors.RayCaster: RayCaster,
    _sensors.TiledCamera: TiledCamera,
}
"""simlab's sensor class -> the class with Isaac Lab 3.0's data access that a 3.0 scene builds instead."""

OffsetCfg = xyzw_class(_FrameOffsetCfg, __name__)
"""The frame transformer's offset (``FrameTransformerCfg.FrameCfg.offset``, ``source_frame_offset``)."""


@configclass
class CameraCfg(_sensors.CameraCfg):
    OffsetCfg = xyzw_class(_sensors.CameraCfg.OffsetCfg, __name__)
    offset: OffsetCfg = OffsetCfg()


@configclass
class TiledCameraCfg(_sensors.TiledCameraCfg):
    OffsetCfg = CameraCfg.OffsetCfg
    offset: OffsetCfg = OffsetCfg()


@configclass
class ImuCfg(_sensors.ImuCfg):
    OffsetCfg = xyzw_class(_sensors.ImuCfg.OffsetCfg, __name__)
    offset: OffsetCfg = OffsetCfg()


@configclass
class RayCasterCfg(_sensors.RayCasterCfg):
    OffsetCfg = xyzw_class(_sensors.RayCasterCfg.OffsetCfg, __name__)
    offset: OffsetCfg = OffsetCfg()
    global_world_only: bool = False
    """3.0's Newton ray caster: cast against the meshes shared by every env only. simlab's ray caster casts
    against ``mesh_prim_paths`` (the ground), the same meshes here."""


@configclass
class FrameTransformerCfg(_sensors.FrameTransformerCfg):
    @configclass
    class FrameCfg(_sensors.FrameTransformerCfg.FrameCfg):
        offset: OffsetCfg = OffsetCfg()

    source_frame_offset: OffsetCfg = OffsetCfg()


def __getattr__(name: str) -> Any:
    return getattr(_sensors, name)
