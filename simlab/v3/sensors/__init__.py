"""``isaaclab.sensors`` of Isaac Lab 3.0: simlab's sensors with ``offset.rot`` in (x, y, z, w) order.

The sensor configs are simlab's (:mod:`simlab.sensors`) with their offsets holding ``rot`` as Isaac
Lab 3.0 writes it. A scene or env of :mod:`simlab.v3` converts them to simlab's order when it is
built (simlab's own scene refuses them, since its sensors read (w, x, y, z)). The other names are
:mod:`simlab.sensors`'s.
"""

from __future__ import annotations

from typing import Any

import simlab.sensors as _sensors
from simlab.sensors.frame_transformer.frame_transformer_cfg import OffsetCfg as _FrameOffsetCfg
from simlab.utils import configclass
from simlab.v3._order import xyzw_class

__all__ = ["CameraCfg", "FrameTransformerCfg", "ImuCfg", "OffsetCfg", "RayCasterCfg", "TiledCameraCfg"]

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


@configclass
class FrameTransformerCfg(_sensors.FrameTransformerCfg):
    @configclass
    class FrameCfg(_sensors.FrameTransformerCfg.FrameCfg):
        offset: OffsetCfg = OffsetCfg()

    source_frame_offset: OffsetCfg = OffsetCfg()


def __getattr__(name: str) -> Any:
    return getattr(_sensors, name)
