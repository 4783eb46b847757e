"""ANYmal-B velocity tracking on flat ground (Isaac Lab's ``Isaac-Velocity-Flat-Anymal-B-v0``)."""

from simlab.utils import configclass

from .rough_env_cfg import AnymalBRoughEnvCfg


@configclass
class AnymalBFlatEnvCfg(AnymalBRoughEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.rewards.flat_orientation_l2.weight = -5.0
        self.rewards.dof_torques_l2.weight = -2.5e-5
        self.rewards.feet_air_time.weight = 0.5
        # a plane, no height scan, no terrain curriculum
        self.scene.terrain.terrain_type = "plane"
        self.scene.terrain.terrain_generator = None
        self.scene.height_scanner = None
        self.observations.policy.height_scan = None
        self.curriculum.terrain_levels = None


@configclass
class AnymalBFlatEnvCfg_PLAY(AnymalBFlatEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self) -> None:
        super().__post_init__()
        self.scene.num_envs = 50
        self.scene.env_spacing = 2.5
        self.observations.policy.enable_corruption = False
        self.events.base_external_force_torque = None
        self.events.push_robot = None
