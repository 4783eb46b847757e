"""Agility Cassie velocity tracking on flat ground (Isaac Lab's ``Isaac-Velocity-Flat-Cassie-v0``)."""

from simlab.utils import configclass

from ..common import flat_ground, play
from .rough_env_cfg import CassieRoughEnvCfg


@configclass
class CassieFlatEnvCfg(CassieRoughEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        # upright, longer steps, only the hip rotation held
        self.rewards.flat_orientation_l2.weight = -2.5
        self.rewards.feet_air_time.weight = 5.0
        self.rewards.joint_deviation_hip.params["asset_cfg"].joint_names = ["hip_rotation_.*"]
        flat_ground(self)


@configclass
class CassieFlatEnvCfg_PLAY(CassieFlatEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self) -> None:
        super().__post_init__()
        play(self, pushes=True)
