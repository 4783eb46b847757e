"""Agility Digit velocity tracking on flat ground (Isaac Lab's ``Isaac-Velocity-Flat-Digit-v0``)."""

from simlab.utils import configclass

from ..common import flat_ground, play
from .rough_env_cfg import DigitRoughEnvCfg


@configclass
class DigitFlatEnvCfg(DigitRoughEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        flat_ground(self)


@configclass
class DigitFlatEnvCfg_PLAY(DigitFlatEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self) -> None:
        super().__post_init__()
        play(self)
