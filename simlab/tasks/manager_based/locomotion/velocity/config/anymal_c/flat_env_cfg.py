"""ANYmal-C velocity tracking on flat ground (Isaac Lab's ``Isaac-Velocity-Flat-Anymal-C-v0``)."""

from simlab.utils import configclass

from ..common import anymal_flat, play
from .rough_env_cfg import AnymalCRoughEnvCfg


@configclass
class AnymalCFlatEnvCfg(AnymalCRoughEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        anymal_flat(self)


@configclass
class AnymalCFlatEnvCfg_PLAY(AnymalCFlatEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self) -> None:
        super().__post_init__()
        play(self)
