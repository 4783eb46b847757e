"""Unitree A1 velocity tracking on flat ground (Isaac Lab's ``Isaac-Velocity-Flat-Unitree-A1-v0``)."""

from simlab.utils import configclass

from ..common import play, unitree_flat
from .rough_env_cfg import UnitreeA1RoughEnvCfg


@configclass
class UnitreeA1FlatEnvCfg(UnitreeA1RoughEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        unitree_flat(self)


@configclass
class UnitreeA1FlatEnvCfg_PLAY(UnitreeA1FlatEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self) -> None:
        super().__post_init__()
        play(self)
