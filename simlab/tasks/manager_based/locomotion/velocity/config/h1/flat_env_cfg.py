"""Unitree H1 velocity tracking on flat ground (Isaac Lab's ``Isaac-Velocity-Flat-H1-v0``)."""

from simlab.utils import configclass

from ..common import flat_ground, play
from .rough_env_cfg import H1RoughEnvCfg


@configclass
class H1FlatEnvCfg(H1RoughEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        flat_ground(self)
        # MuJoCo Warp's buffers per world from the measured worst case, the robot fallen on the ground
        # (11 contacts, 44 rows; tests/test_humanoid_velocity.py), 1.5 times over and up to a multiple
        # of 16 (its row tiles): its estimate reserved 48 and 102
        self.sim.mujoco.nconmax = 24
        self.sim.mujoco.njmax = 80
        # longer steps on flat ground
        self.rewards.feet_air_time.weight = 1.0
        self.rewards.feet_air_time.params["threshold"] = 0.6


@configclass
class H1FlatEnvCfg_PLAY(H1FlatEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self) -> None:
        super().__post_init__()
        play(self)
