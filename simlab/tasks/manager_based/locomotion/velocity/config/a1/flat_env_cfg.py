"""Unitree A1 velocity tracking on flat ground (Isaac Lab's ``Isaac-Velocity-Flat-Unitree-A1-v0``)."""

from simlab.utils import configclass

from .rough_env_cfg import UnitreeA1RoughEnvCfg


@configclass
class UnitreeA1FlatEnvCfg(UnitreeA1RoughEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.rewards.flat_orientation_l2.weight = -2.5
        self.rewards.feet_air_time.weight = 0.25
        # a plane, no height scan, no terrain curriculum
        self.scene.terrain.terrain_type = "plane"
        self.scene.terrain.terrain_generator = None
        self.scene.height_scanner = None
        self.observations.policy.height_scan = None
        self.curriculum.terrain_levels = None


@configclass
class UnitreeA1FlatEnvCfg_PLAY(UnitreeA1FlatEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self) -> None:
        super().__post_init__()
        self.scene.num_envs = 50
        self.scene.env_spacing = 2.5
        self.observations.policy.enable_corruption = False
        self.events.base_external_force_torque = None
        self.events.push_robot = None
