"""Unitree A1 velocity tracking on rough terrain (Isaac Lab's ``Isaac-Velocity-Rough-Unitree-A1-v0``)."""

from simlab.robots.unitree import UNITREE_A1_CFG
from simlab.tasks.manager_based.locomotion.velocity.velocity_env_cfg import LocomotionVelocityRoughEnvCfg
from simlab.utils import configclass

from ..common import play, unitree_rough


@configclass
class UnitreeA1RoughEnvCfg(LocomotionVelocityRoughEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        unitree_rough(self, UNITREE_A1_CFG, base="trunk")


@configclass
class UnitreeA1RoughEnvCfg_PLAY(UnitreeA1RoughEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self):
        super().__post_init__()
        play(self)
