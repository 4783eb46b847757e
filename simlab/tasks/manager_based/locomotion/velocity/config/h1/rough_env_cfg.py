"""Unitree H1 velocity tracking on rough terrain (Isaac Lab's ``Isaac-Velocity-Rough-H1-v0``).

The biped rewards of the G1 task (see ``config/g1``) with H1's joints: the velocity tracked in the
yaw frame and the yaw rate in the world frame, single-support steps, feet that do not slide, hip
yaw and roll, arms and torso held near their default, ankles kept off their limits, a large
penalty for falling. Commands are forward-only on rough ground.

Tuned for MuJoCo as the G1's (see ``config/g1/rough_env_cfg.py``): both tracking terms weighted 2
(Isaac Lab's: 1 and 1), which makes walking pay against standing still, and a fall ends the episode at
70 degrees of tilt (mjlab's) as well as when the torso touches the ground. H1 keeps Isaac Lab's gains
and 0.5 action scale: against its motors' limits (hips 200, knees 300, ankles 40 N m) a unit of action
asks 0.25-0.5 of the effort limit, near mjlab's rule of a quarter (the G1's asked up to 1.1)."""

from simlab.managers import RewardTermCfg as RewTerm
from simlab.managers import SceneEntityCfg
from simlab.robots import H1_MINIMAL_CFG
from simlab.tasks.manager_based.locomotion.velocity import mdp
from simlab.tasks.manager_based.locomotion.velocity.velocity_env_cfg import (
    LocomotionVelocityRoughEnvCfg,
    RewardsCfg,
)
from simlab.utils import configclass

from ..common import humanoid_play, humanoid_rough

FEET = ".*ankle_link"


@configclass
class H1Rewards(RewardsCfg):
    termination_penalty = RewTerm(func=mdp.is_terminated, weight=-200.0)
    lin_vel_z_l2 = None
    track_lin_vel_xy_exp = RewTerm(
        func=mdp.track_lin_vel_xy_yaw_frame_exp, weight=2.0, params={"command_name": "base_velocity", "std": 0.5}
    )
    track_ang_vel_z_exp = RewTerm(
        func=mdp.track_ang_vel_z_world_exp, weight=2.0, params={"command_name": "base_velocity", "std": 0.5}
    )
    feet_air_time = RewTerm(
        func=mdp.feet_air_time_positive_biped,
        weight=0.25,
        params={
            "command_name": "base_velocity",
            "sensor_cfg": SceneEntityCfg("contact_forces", body_names=FEET),
            "threshold": 0.4,
        },
    )
    feet_slide = RewTerm(
        func=mdp.feet_slide,
        weight=-0.25,
        params={
            "sensor_cfg": SceneEntityCfg("contact_forces", body_names=FEET),
            "asset_cfg": SceneEntityCfg("robot", body_names=FEET),
        },
    )
    dof_pos_limits = RewTerm(
        func=mdp.joint_pos_limits, weight=-1.0, params={"asset_cfg": SceneEntityCfg("robot", joint_names=".*_ankle")}
    )
    joint_deviation_hip = RewTerm(
        func=mdp.joint_deviation_l1,
        weight=-0.2,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=[".*_hip_yaw", ".*_hip_roll"])},
    )
    joint_deviation_arms = RewTerm(
        func=mdp.joint_deviation_l1,
        weight=-0.2,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=[".*_shoulder_.*", ".*_elbow"])},
    )
    joint_deviation_torso = RewTerm(
        func=mdp.joint_deviation_l1, weight=-0.1, params={"asset_cfg": SceneEntityCfg("robot", joint_names="torso")}
    )


@configclass
class H1RoughEnvCfg(LocomotionVelocityRoughEnvCfg):
    rewards: H1Rewards = H1Rewards()

    def __post_init__(self):
        super().__post_init__()
        # no pushes or mass changes, start at rest; forward and turning commands; a fall ends at 70 degrees
        humanoid_rough(self, H1_MINIMAL_CFG, torso=".*torso_link")
        # MuJoCo Warp's buffers per world from the measured worst case, the robot fallen on the hardest
        # terrains (33 contacts, 132 rows over 320 worlds; tests/test_height_scan_cost.py), 1.5 times over
        # and up to a multiple of 16: its estimate reserved 192 and 1574 (random actions: 15 and 60)
        self.sim.mujoco.nconmax = 64
        self.sim.mujoco.njmax = 208
        self.rewards.dof_torques_l2.weight = 0.0


@configclass
class H1RoughEnvCfg_PLAY(H1RoughEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self):
        super().__post_init__()
        humanoid_play(self)
