"""Unitree Go2 velocity tracking on rough terrain (Isaac Lab's ``Isaac-Velocity-Rough-Unitree-Go2-v0``)."""

from simlab.robots.unitree import UNITREE_GO2_CFG
from simlab.tasks.manager_based.locomotion.velocity.velocity_env_cfg import LocomotionVelocityRoughEnvCfg
from simlab.utils import configclass

from ..common import play, unitree_rough


@configclass
class UnitreeGo2RoughEnvCfg(LocomotionVelocityRoughEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        unitree_rough(self, UNITREE_GO2_CFG, base="base")


@configclass
class UnitreeGo2RoughEnvCfg_PLAY(UnitreeGo2RoughEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self):
        super().__post_init__()
        play(self)
