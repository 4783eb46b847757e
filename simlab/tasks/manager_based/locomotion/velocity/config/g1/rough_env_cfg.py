"""Unitree G1 velocity tracking on rough terrain (Isaac Lab's ``Isaac-Velocity-Rough-G1-v0``).

A biped's rewards: the velocity tracked in the yaw frame and the yaw rate in the world frame, steps
rewarded in single support, feet that do not slide, the joints that do not walk (hip yaw and roll,
torso, arms, fingers) held near their default, ankles kept off their limits, and a large penalty for
falling. Commands are forward-only on rough ground.

Tuned for MuJoCo where Isaac Lab's PhysX values kept the robot standing (G1 flat on an H100: 806
iterations, episodes of 1000 steps, yet a mean speed error of 0.57 m/s at every checkpoint, what a
robot that never moves scores on these commands). From mjlab's G1, which learns to walk on MuJoCo:
the motor model (``G1_MOTOR_MODEL_CFG``) and its per-joint action scale instead of kp 150-200 at a
0.5 scale; the policy drives the 23 joints that walk, not the 14 finger joints (held at their
default by their drives); velocity tracking weighted 2 for both terms (Isaac Lab's flat G1: 1 and 1),
which makes walking pay against the standing optimum; a fall ends the episode at 70 degrees of tilt
(mjlab's), not only when the torso touches the ground.
"""

from simlab.managers import RewardTermCfg as RewTerm
from simlab.managers import SceneEntityCfg
from simlab.robots.unitree import G1_BODY_JOINTS, G1_MOTOR_MODEL_ACTION_SCALE, G1_MOTOR_MODEL_CFG
from simlab.tasks.manager_based.locomotion.velocity import mdp
from simlab.tasks.manager_based.locomotion.velocity.velocity_env_cfg import (
    LocomotionVelocityRoughEnvCfg,
    RewardsCfg,
)
from simlab.utils import configclass

from ..common import humanoid_play, humanoid_rough

FEET = ".*_ankle_roll_link"
ARM_JOINTS = [f".*_{j}_joint" for j in ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow_pitch", "elbow_roll")]
FINGER_JOINTS = [f".*_{f}_joint" for f in ("five", "three", "six", "four", "zero", "one", "two")]


@configclass
class G1Rewards(RewardsCfg):
    termination_penalty = RewTerm(func=mdp.is_terminated, weight=-200.0)
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
        weight=-0.1,
        params={
            "sensor_cfg": SceneEntityCfg("contact_forces", body_names=FEET),
            "asset_cfg": SceneEntityCfg("robot", body_names=FEET),
        },
    )
    dof_pos_limits = RewTerm(
        func=mdp.joint_pos_limits,
        weight=-1.0,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=[".*_ankle_pitch_joint", ".*_ankle_roll_joint"])},
    )
    joint_deviation_hip = RewTerm(
        func=mdp.joint_deviation_l1,
        weight=-0.1,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=[".*_hip_yaw_joint", ".*_hip_roll_joint"])},
    )
    joint_deviation_arms = RewTerm(
        func=mdp.joint_deviation_l1, weight=-0.1, params={"asset_cfg": SceneEntityCfg("robot", joint_names=ARM_JOINTS)}
    )
    joint_deviation_fingers = RewTerm(
        func=mdp.joint_deviation_l1,
        weight=-0.05,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=FINGER_JOINTS)},
    )
    joint_deviation_torso = RewTerm(
        func=mdp.joint_deviation_l1,
        weight=-0.1,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names="torso_joint")},
    )


@configclass
class G1RoughEnvCfg(LocomotionVelocityRoughEnvCfg):
    rewards: G1Rewards = G1Rewards()

    def __post_init__(self):
        super().__post_init__()
        # no pushes or mass changes, start at rest; forward and turning commands; a fall ends at 70 degrees
        humanoid_rough(self, G1_MOTOR_MODEL_CFG, torso="torso_link")
        # MuJoCo Warp's buffers per world from the measured worst case, the robot fallen on the hardest
        # terrains (41 contacts, 166 rows over 320 worlds; tests/test_height_scan_cost.py), 1.5 times over
        # and up to a multiple of 16: its estimate reserved 256 and 2122 (random actions: 12 and 48)
        self.sim.mujoco.nconmax = 64
        self.sim.mujoco.njmax = 256
        # the policy drives and sees the 23 joints that walk, each scaled by its motor (mjlab's rule)
        self.actions.joint_pos.joint_names = list(G1_BODY_JOINTS)
        self.actions.joint_pos.scale = dict(G1_MOTOR_MODEL_ACTION_SCALE)
        for term in (self.observations.policy.joint_pos, self.observations.policy.joint_vel):
            term.params["asset_cfg"] = SceneEntityCfg("robot", joint_names=list(G1_BODY_JOINTS))
        # rewards: joint accelerations and torques of the legs only
        self.rewards.lin_vel_z_l2.weight = 0.0
        self.rewards.dof_acc_l2.params["asset_cfg"] = SceneEntityCfg(
            "robot", joint_names=[".*_hip_.*", ".*_knee_joint"]
        )
        self.rewards.dof_torques_l2.weight = -1.5e-7
        self.rewards.dof_torques_l2.params["asset_cfg"] = SceneEntityCfg(
            "robot", joint_names=[".*_hip_.*", ".*_knee_joint", ".*_ankle_.*"]
        )


@configclass
class G1RoughEnvCfg_PLAY(G1RoughEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self):
        super().__post_init__()
        humanoid_play(self)
