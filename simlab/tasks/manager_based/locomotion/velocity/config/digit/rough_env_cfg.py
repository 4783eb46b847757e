"""Agility Digit velocity tracking on rough terrain (Isaac Lab's ``Isaac-Velocity-Rough-Digit-v0``).

Isaac Lab's Digit terms: a large penalty for falling, velocity tracked in the yaw frame and the yaw rate
in the world frame, single-support steps of up to 0.8 s, feet that do not slide and do not both leave
the ground, the hips, tarsi, toe motors and arms held near their default (the legs' motors all the more
while the command is to stand), the passive foot and tarsus joints kept off their limits, and no touch
on the rods or tarsi. The policy drives the 26 motors (12 leg, 14 arm), observes their positions and
velocities, and ends at a torso contact or 40 degrees of tilt. Starts at the default pose (no joint
randomisation: the loops close only there), 5 ms physics steps, 4 per policy step.

Tuned for MuJoCo as the G1 and H1 are (docs/humanoids.md), where Isaac Lab's values left the robot
falling within a second (CPU, 256 envs, seed 42, 40 iterations: episodes of 42-50 steps throughout):
mjlab's motor model (``DIGIT_V4_MOTOR_MODEL_CFG``: 10 Hz gains on each motor's reflected inertia, where
kp 200 / kd 5 let the knees give 0.6 rad under the robot's weight) with its per-joint action scale
instead of a 0.5 scale; velocity tracking weighted 2 for both terms, which makes walking pay against
the falls' penalty; the bipeds' events (start at rest, no pushes, no payload; Isaac Lab's reset throws
the robot at up to 0.5 m/s and 0.5 rad/s). With these, at the runner's action noise of 1.0, the same
run's episodes grow from 70 to 104 steps and its speed tracking reward is four times that of Isaac
Lab's settings at noise 0.5 (docs/locomotion.md has each change alone).
"""

import math

from simlab.managers import ObservationGroupCfg as ObsGroup
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.managers import RewardTermCfg as RewTerm
from simlab.managers import SceneEntityCfg
from simlab.managers import TerminationTermCfg as DoneTerm
from simlab.robots.agility import (
    ARM_JOINT_NAMES,
    DIGIT_V4_MOTOR_MODEL_ACTION_SCALE,
    DIGIT_V4_MOTOR_MODEL_CFG,
    LEG_JOINT_NAMES,
)
from simlab.tasks.manager_based.locomotion.velocity import mdp
from simlab.tasks.manager_based.locomotion.velocity.velocity_env_cfg import LocomotionVelocityRoughEnvCfg
from simlab.utils import configclass
from simlab.utils.noise import AdditiveUniformNoiseCfg as Unoise

from ..common import biped_events, play

MOTORS = LEG_JOINT_NAMES + ARM_JOINT_NAMES
FEET = ".*_leg_toe_roll"


# Isaac Lab's class names: its loco-manipulation task imports DigitRewards from here
@configclass
class DigitRewards:
    termination_penalty = RewTerm(func=mdp.is_terminated, weight=-100.0)
    track_lin_vel_xy_exp = RewTerm(
        func=mdp.track_lin_vel_xy_yaw_frame_exp,
        weight=1.0,
        params={"command_name": "base_velocity", "std": math.sqrt(0.25)},
    )
    track_ang_vel_z_exp = RewTerm(
        func=mdp.track_ang_vel_z_world_exp, weight=1.0, params={"command_name": "base_velocity", "std": math.sqrt(0.25)}
    )
    feet_air_time = RewTerm(
        func=mdp.feet_air_time_positive_biped,
        weight=0.25,
        params={
            "sensor_cfg": SceneEntityCfg("contact_forces", body_names=FEET),
            "threshold": 0.8,
            "command_name": "base_velocity",
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
    dof_torques_l2 = RewTerm(func=mdp.joint_torques_l2, weight=-1.0e-6)
    dof_acc_l2 = RewTerm(
        func=mdp.joint_acc_l2, weight=-2.0e-7, params={"asset_cfg": SceneEntityCfg("robot", joint_names=MOTORS)}
    )
    action_rate_l2 = RewTerm(func=mdp.action_rate_l2, weight=-0.008)
    flat_orientation_l2 = RewTerm(func=mdp.flat_orientation_l2, weight=-2.5)
    stand_still = RewTerm(
        func=mdp.stand_still_joint_deviation_l1,
        weight=-0.4,
        params={"command_name": "base_velocity", "asset_cfg": SceneEntityCfg("robot", joint_names=LEG_JOINT_NAMES)},
    )
    lin_vel_z_l2 = RewTerm(func=mdp.lin_vel_z_l2, weight=-2.0)
    ang_vel_xy_l2 = RewTerm(func=mdp.ang_vel_xy_l2, weight=-0.1)
    no_jumps = RewTerm(
        func=mdp.desired_contacts,
        weight=-0.5,
        params={"sensor_cfg": SceneEntityCfg("contact_forces", body_names=[FEET])},
    )
    dof_pos_limits = RewTerm(
        func=mdp.joint_pos_limits,
        weight=-1.0,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=[".*_leg_toe_roll", ".*_leg_toe_pitch", ".*_tarsus"])},
    )
    joint_deviation_hip_roll = RewTerm(
        func=mdp.joint_deviation_l1,
        weight=-0.1,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=".*_leg_hip_roll")},
    )
    joint_deviation_hip_yaw = RewTerm(
        func=mdp.joint_deviation_l1,
        weight=-0.2,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=".*_leg_hip_yaw")},
    )
    joint_deviation_knee = RewTerm(  # Isaac Lab's name; it holds the tarsus, which follows the knee
        func=mdp.joint_deviation_l1,
        weight=-0.2,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=".*_tarsus")},
    )
    joint_deviation_feet = RewTerm(
        func=mdp.joint_deviation_l1,
        weight=-0.1,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=[".*_toe_a", ".*_toe_b"])},
    )
    joint_deviation_arms = RewTerm(
        func=mdp.joint_deviation_l1,
        weight=-0.2,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=".*_arm_.*")},
    )
    undesired_contacts = RewTerm(
        func=mdp.undesired_contacts,
        weight=-0.1,
        params={"sensor_cfg": SceneEntityCfg("contact_forces", body_names=[".*_rod", ".*_tarsus"]), "threshold": 1.0},
    )


@configclass
class DigitObservations:
    @configclass
    class PolicyCfg(ObsGroup):
        base_lin_vel = ObsTerm(func=mdp.base_lin_vel, noise=Unoise(n_min=-0.1, n_max=0.1))
        base_ang_vel = ObsTerm(func=mdp.base_ang_vel, noise=Unoise(n_min=-0.2, n_max=0.2))
        projected_gravity = ObsTerm(func=mdp.projected_gravity, noise=Unoise(n_min=-0.05, n_max=0.05))
        velocity_commands = ObsTerm(func=mdp.generated_commands, params={"command_name": "base_velocity"})
        joint_pos = ObsTerm(
            func=mdp.joint_pos_rel,
            params={"asset_cfg": SceneEntityCfg("robot", joint_names=MOTORS)},
            noise=Unoise(n_min=-0.01, n_max=0.01),
        )
        joint_vel = ObsTerm(
            func=mdp.joint_vel_rel,
            params={"asset_cfg": SceneEntityCfg("robot", joint_names=MOTORS)},
            noise=Unoise(n_min=-1.5, n_max=1.5),
        )
        actions = ObsTerm(func=mdp.last_action)
        height_scan = ObsTerm(
            func=mdp.height_scan,
            params={"sensor_cfg": SceneEntityCfg("height_scanner")},
            noise=Unoise(n_min=-0.1, n_max=0.1),
            clip=(-1.0, 1.0),
        )

        def __post_init__(self):
            self.enable_corruption = True
            self.concatenate_terms = True

    policy: PolicyCfg = PolicyCfg()


@configclass
class DigitTerminationsCfg:
    time_out = DoneTerm(func=mdp.time_out, time_out=True)
    base_contact = DoneTerm(
        func=mdp.illegal_contact,
        params={"sensor_cfg": SceneEntityCfg("contact_forces", body_names=["torso_base"]), "threshold": 1.0},
    )
    base_orientation = DoneTerm(func=mdp.bad_orientation, params={"limit_angle": 0.7})


@configclass
class DigitActionsCfg:
    joint_pos = mdp.JointPositionActionCfg(asset_name="robot", joint_names=MOTORS, scale=0.5, use_default_offset=True)


@configclass
class DigitRoughEnvCfg(LocomotionVelocityRoughEnvCfg):
    rewards: DigitRewards = DigitRewards()
    observations: DigitObservations = DigitObservations()
    terminations: DigitTerminationsCfg = DigitTerminationsCfg()
    actions: DigitActionsCfg = DigitActionsCfg()

    def __post_init__(self):
        super().__post_init__()
        self.decimation = 4
        self.sim.dt = 0.005
        self.scene.robot = DIGIT_V4_MOTOR_MODEL_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        self.actions.joint_pos.scale = dict(DIGIT_V4_MOTOR_MODEL_ACTION_SCALE)
        if self.scene.height_scanner:
            self.scene.height_scanner.prim_path = "{ENV_REGEX_NS}/Robot/torso_base"
            self.scene.height_scanner.update_period = self.decimation * self.sim.dt
        self.scene.contact_forces.history_length = self.decimation
        self.scene.contact_forces.update_period = self.sim.dt
        # rewards: walking pays against the falls' penalty (Isaac Lab: 1 and 1)
        self.rewards.track_lin_vel_xy_exp.weight = 2.0
        self.rewards.track_ang_vel_z_exp.weight = 2.0
        # events: the bipeds' (start at rest in the default pose, where the rods close; no pushes, no
        # payload or centre-of-mass change), the zero external force on the torso
        biped_events(self, "torso_base")
        # commands
        self.commands.base_velocity.ranges.lin_vel_x = (-0.8, 0.8)
        self.commands.base_velocity.ranges.lin_vel_y = (-0.5, 0.5)
        self.commands.base_velocity.ranges.ang_vel_z = (-1.0, 1.0)
        self.commands.base_velocity.rel_standing_envs = 0.1
        self.commands.base_velocity.resampling_time_range = (3.0, 8.0)


@configclass
class DigitRoughEnvCfg_PLAY(DigitRoughEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self):
        super().__post_init__()
        play(self)
