"""Unitree Go2 velocity tracking on flat ground (Isaac Lab's ``Isaac-Velocity-Flat-Unitree-Go2-v0``)."""

from simlab.utils import configclass

from ..common import play, unitree_flat
from .rough_env_cfg import UnitreeGo2RoughEnvCfg


@configclass
class UnitreeGo2FlatEnvCfg(UnitreeGo2RoughEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        unitree_flat(self)


@configclass
class UnitreeGo2FlatEnvCfg_PLAY(UnitreeGo2FlatEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self) -> None:
        super().__post_init__()
        play(self)
