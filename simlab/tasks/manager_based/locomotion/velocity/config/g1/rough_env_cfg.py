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

import math

from simlab.managers import RewardTermCfg as RewTerm
from simlab.managers import SceneEntityCfg
from simlab.managers import TerminationTermCfg as DoneTerm
from simlab.robots.unitree import G1_BODY_JOINTS, G1_MOTOR_MODEL_ACTION_SCALE, G1_MOTOR_MODEL_CFG
from simlab.tasks.manager_based.locomotion.velocity import mdp
from simlab.tasks.manager_based.locomotion.velocity.velocity_env_cfg import (
    LocomotionVelocityRoughEnvCfg,
    RewardsCfg,
)
from simlab.utils import configclass

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
        self.scene.robot = G1_MOTOR_MODEL_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        # the policy drives and sees the 23 joints that walk, each scaled by its motor (mjlab's rule)
        self.actions.joint_pos.joint_names = list(G1_BODY_JOINTS)
        self.actions.joint_pos.scale = dict(G1_MOTOR_MODEL_ACTION_SCALE)
        for term in (self.observations.policy.joint_pos, self.observations.policy.joint_vel):
            term.params["asset_cfg"] = SceneEntityCfg("robot", joint_names=list(G1_BODY_JOINTS))
        self.scene.height_scanner.prim_path = "{ENV_REGEX_NS}/Robot/torso_link"
        # events: no pushes or mass and centre-of-mass changes; start at the default pose, at rest
        self.events.push_robot = None
        self.events.add_base_mass = None
        self.events.base_com = None
        self.events.reset_robot_joints.params["position_range"] = (1.0, 1.0)
        self.events.base_external_force_torque.params["asset_cfg"].body_names = ["torso_link"]
        self.events.reset_base.params = {
            "pose_range": {"x": (-0.5, 0.5), "y": (-0.5, 0.5), "yaw": (-3.14, 3.14)},
            "velocity_range": {k: (0.0, 0.0) for k in ("x", "y", "z", "roll", "pitch", "yaw")},
        }
        # rewards
        self.rewards.lin_vel_z_l2.weight = 0.0
        self.rewards.undesired_contacts = None
        self.rewards.flat_orientation_l2.weight = -1.0
        self.rewards.action_rate_l2.weight = -0.005
        self.rewards.dof_acc_l2.weight = -1.25e-7
        self.rewards.dof_acc_l2.params["asset_cfg"] = SceneEntityCfg(
            "robot", joint_names=[".*_hip_.*", ".*_knee_joint"]
        )
        self.rewards.dof_torques_l2.weight = -1.5e-7
        self.rewards.dof_torques_l2.params["asset_cfg"] = SceneEntityCfg(
            "robot", joint_names=[".*_hip_.*", ".*_knee_joint", ".*_ankle_.*"]
        )
        # commands: forward and turning only
        self.commands.base_velocity.ranges.lin_vel_x = (0.0, 1.0)
        self.commands.base_velocity.ranges.lin_vel_y = (0.0, 0.0)
        self.commands.base_velocity.ranges.ang_vel_z = (-1.0, 1.0)
        # terminations: the torso on the ground, or tilted past 70 degrees (mjlab's fall, caught sooner)
        self.terminations.base_contact.params["sensor_cfg"].body_names = "torso_link"
        self.terminations.fell_over = DoneTerm(func=mdp.bad_orientation, params={"limit_angle": math.radians(70.0)})


@configclass
class G1RoughEnvCfg_PLAY(G1RoughEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self):
        super().__post_init__()
        self.scene.num_envs = 50
        self.scene.env_spacing = 2.5
        self.episode_length_s = 40.0
        # spawn anywhere on a smaller grid instead of on the curriculum's levels
        self.scene.terrain.max_init_terrain_level = None
        if self.scene.terrain.terrain_generator is not None:
            self.scene.terrain.terrain_generator.num_rows = 5
            self.scene.terrain.terrain_generator.num_cols = 5
            self.scene.terrain.terrain_generator.curriculum = False
        self.commands.base_velocity.ranges.lin_vel_x = (1.0, 1.0)
        self.commands.base_velocity.ranges.lin_vel_y = (0.0, 0.0)
        self.commands.base_velocity.ranges.ang_vel_z = (-1.0, 1.0)
        self.commands.base_velocity.ranges.heading = (0.0, 0.0)
        self.observations.policy.enable_corruption = False
        self.events.base_external_force_torque = None
        self.events.push_robot = None
