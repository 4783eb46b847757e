"""Agility Digit walking to velocity commands while each hand tracks a pose command (Isaac Lab's
``Isaac-Tracking-LocoManip-Digit-v0``).

Isaac Lab's task on top of its Digit velocity task, on flat ground: the velocity command steers by
heading (its class writes 10 s windows, a quarter of the robots standing, 1 m/s in x and y, but the
velocity task's ``__post_init__``, which runs after, sets 3 to 8 s, a tenth standing, 0.8 m/s in x and
0.5 m/s in y, as in Isaac Lab), and each hand (the ``<side>_arm_wrist_yaw`` body, the last link of
the seven-joint arm) gets a pose in the torso's frame every 1 to 3 s: 0.1 to 0.5 m ahead, 0.05 to
0.5 m out to its side, within 0.2 m of the torso's origin in height, palm turned inwards (yaw +-90
degrees) within 0.1 rad. Rewards: the velocity task's, less holding the arms at their default, plus
the hands' distance (-2), its fine-grained tanh (+2, 5 cm) and orientation error (-0.2), hip-yaw
speed (-0.001), and a level torso weighed -10.5. The policy also observes both pose commands.
Episodes last 14 s.

Isaac Lab's file also writes an event group with a payload force on each hand but never sets it on the
env config, so its task runs the velocity task's events; so does this one (no hand forces).

On simlab's Digit (``simlab/robots/assets/agility_digit.xml``) the shoulders sit 0.4 m above the
torso's origin and the hand 0.61 m from the shoulder joint, so some commanded positions lie out of
reach: 29 % of them are farther from the shoulder than that (docs/locomotion.md).

Through the velocity task it takes simlab's MuJoCo tuning (the motor model, its leg action scale,
tracking weighted 2, resets at rest): with zero actions every robot stands 74 steps, against 30-72
under Isaac Lab's settings. The arms keep Isaac Lab's 0.5 rad per unit of action: at the motor
model's 0.04-0.08 rad, three units of action reached within 5 cm of 1 % of the commanded hand
positions and a 40-iteration CPU run left the hands 0.41 m from them; at 0.5, 71 % (all the arm can
reach) and 0.30 m. The arms start with the forearms forward, each hand in the middle of its command box
(``ARM_POSE``), not hanging: hanging 0.42 m and 90 degrees from its commands, the hands cost a robot alive
more per second than the termination penalty is worth over PPO's horizon, so falling paid
(``agents/rsl_rl_ppo_cfg.py``, tests/test_digit_locomanip.py).
"""

import math
import re

from simlab.managers import ObservationGroupCfg as ObsGroup
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.managers import RewardTermCfg as RewTerm
from simlab.managers import SceneEntityCfg
from simlab.robots.agility import ARM_JOINT_NAMES, LEG_JOINT_NAMES
from simlab.tasks.manager_based.locomotion.velocity import mdp
from simlab.tasks.manager_based.locomotion.velocity.config.digit.rough_env_cfg import DigitRewards, DigitRoughEnvCfg
from simlab.tasks.manager_based.manipulation.reach import mdp as manipulation_mdp
from simlab.utils import configclass
from simlab.utils.noise import AdditiveUniformNoiseCfg as Unoise

MOTORS = LEG_JOINT_NAMES + ARM_JOINT_NAMES
HANDS = {"left": "left_arm_wrist_yaw", "right": "right_arm_wrist_yaw"}
"""Each side's end effector: Isaac Lab's body names, which simlab's Digit has too."""
ARM_JOINTS = [
    f"{side}_arm_{joint}"
    for side in ("left", "right")
    for joint in ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow", "wrist_roll", "wrist_pitch", "wrist_yaw")
]
ARM_ACTION_SCALE = 0.5
"""Arm targets per unit of action [rad]: Isaac Lab's scale. The velocity task's motor-model rule (a
quarter of the effort limit over the stiffness) gives the arms 0.04-0.08 rad, with which the hands
reach almost none of the commanded positions (docs/locomotion.md)."""


ARM_POSE = {
    "shoulder_pitch": -0.05,
    "shoulder_roll": 0.17,
    "shoulder_yaw": 0.07,
    "elbow": -1.10,
    "wrist_roll": 0.18,
    "wrist_pitch": -0.40,
    "wrist_yaw": -0.15,
}
"""The left arm's default pose [rad]: upper arm hanging, forearm forward, the hand at the middle of its
command box (0.3 m ahead, 0.275 m out, level with the torso's origin) in the commands' middle orientation
(damped least squares on the MJCF from the upper arm hanging and the elbow bent). Hanging straight, the
hands started 0.42 m and 90 degrees from their commands on average; here 0.20 m."""
MIRRORED = {"shoulder_pitch", "elbow", "wrist_pitch"}
"""The arm joints about the y axis, whose angle the right arm shares; the others change sign."""


def _arm_pose() -> dict[str, float]:
    """Both arms' joints at ``ARM_POSE``, the right arm mirroring the left."""
    return {
        f"{side}_arm_{joint}": q if side == "left" or joint in MIRRORED else -q
        for side in ("left", "right")
        for joint, q in ARM_POSE.items()
    }


def _with_arm_scale(scale: dict[str, float], arm_scale: float) -> dict[str, float]:
    """``scale`` (joint pattern -> scale) with every arm joint at ``arm_scale``, the legs' kept."""
    legs = {key: value for key, value in scale.items() if not any(re.fullmatch(key, arm) for arm in ARM_JOINTS)}
    return {**legs, ARM_JOINT_NAMES[0]: arm_scale}


def _hand(side: str) -> dict:
    return {"asset_cfg": SceneEntityCfg("robot", body_names=HANDS[side]), "command_name": f"{side}_ee_pose"}


def _position_error(side: str) -> RewTerm:
    return RewTerm(func=manipulation_mdp.position_command_error, weight=-2.0, params=_hand(side))


def _position_error_tanh(side: str) -> RewTerm:
    return RewTerm(func=manipulation_mdp.position_command_error_tanh, weight=2.0, params={**_hand(side), "std": 0.05})


def _orientation_error(side: str) -> RewTerm:
    return RewTerm(func=manipulation_mdp.orientation_command_error, weight=-0.2, params=_hand(side))


@configclass
class DigitLocoManipRewards(DigitRewards):
    joint_deviation_arms = None  # the arms move to the hand commands
    joint_vel_hip_yaw = RewTerm(
        func=mdp.joint_vel_l2,
        weight=-0.001,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=".*_leg_hip_yaw")},
    )
    left_ee_pos_tracking = _position_error("left")
    left_ee_pos_tracking_fine_grained = _position_error_tanh("left")
    left_end_effector_orientation_tracking = _orientation_error("left")
    right_ee_pos_tracking = _position_error("right")
    right_ee_pos_tracking_fine_grained = _position_error_tanh("right")
    right_end_effector_orientation_tracking = _orientation_error("right")


@configclass
class DigitLocoManipObservations:
    @configclass
    class PolicyCfg(ObsGroup):
        base_lin_vel = ObsTerm(func=mdp.base_lin_vel, noise=Unoise(n_min=-0.1, n_max=0.1))
        base_ang_vel = ObsTerm(func=mdp.base_ang_vel, noise=Unoise(n_min=-0.2, n_max=0.2))
        projected_gravity = ObsTerm(func=mdp.projected_gravity, noise=Unoise(n_min=-0.05, n_max=0.05))
        velocity_commands = ObsTerm(func=mdp.generated_commands, params={"command_name": "base_velocity"})
        left_ee_pose_command = ObsTerm(func=mdp.generated_commands, params={"command_name": "left_ee_pose"})
        right_ee_pose_command = ObsTerm(func=mdp.generated_commands, params={"command_name": "right_ee_pose"})
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

        def __post_init__(self):
            self.enable_corruption = True
            self.concatenate_terms = True

    policy: PolicyCfg = PolicyCfg()


def _hand_command(side: str) -> mdp.UniformPoseCommandCfg:
    sign = 1.0 if side == "left" else -1.0
    y = (0.05, 0.50) if side == "left" else (-0.50, -0.05)
    return mdp.UniformPoseCommandCfg(
        asset_name="robot",
        body_name=HANDS[side],
        resampling_time_range=(1.0, 3.0),
        debug_vis=True,
        ranges=mdp.UniformPoseCommandCfg.Ranges(
            pos_x=(0.10, 0.50),
            pos_y=y,
            pos_z=(-0.20, 0.20),
            roll=(-0.1, 0.1),
            pitch=(-0.1, 0.1),
            yaw=(sign * math.pi / 2.0 - 0.1, sign * math.pi / 2.0 + 0.1),
        ),
    )


@configclass
class DigitLocoManipCommands:
    base_velocity = mdp.UniformVelocityCommandCfg(
        asset_name="robot",
        resampling_time_range=(10.0, 10.0),
        rel_standing_envs=0.25,
        rel_heading_envs=1.0,
        heading_command=True,
        debug_vis=True,
        ranges=mdp.UniformVelocityCommandCfg.Ranges(
            lin_vel_x=(-1.0, 1.0), lin_vel_y=(-1.0, 1.0), ang_vel_z=(-1.0, 1.0), heading=(-math.pi, math.pi)
        ),
    )
    left_ee_pose = _hand_command("left")
    right_ee_pose = _hand_command("right")


@configclass
class DigitLocoManipEnvCfg(DigitRoughEnvCfg):
    rewards: DigitLocoManipRewards = DigitLocoManipRewards()
    observations: DigitLocoManipObservations = DigitLocoManipObservations()
    commands: DigitLocoManipCommands = DigitLocoManipCommands()

    def __post_init__(self):
        super().__post_init__()
        self.episode_length_s = 14.0
        self.rewards.flat_orientation_l2.weight = -10.5
        self.rewards.termination_penalty.weight = -100.0
        # the legs keep the velocity task's motor-model scale; the arms reach for the hand commands
        self.actions.joint_pos.scale = _with_arm_scale(self.actions.joint_pos.scale, ARM_ACTION_SCALE)
        # the arms start (and their actions are offsets from) the hands in the middle of their commands
        legs = {k: v for k, v in self.scene.robot.init_state.joint_pos.items() if k != ARM_JOINT_NAMES[0]}
        self.scene.robot.init_state.joint_pos = {**legs, **_arm_pose()}
        # flat ground: no height scan, no terrain curriculum
        self.scene.terrain.terrain_type = "plane"
        self.scene.terrain.terrain_generator = None
        self.scene.height_scanner = None
        self.observations.policy.height_scan = None
        self.curriculum.terrain_levels = None


@configclass
class DigitLocoManipEnvCfg_PLAY(DigitLocoManipEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self) -> None:
        super().__post_init__()
        self.scene.num_envs = 50
        self.scene.env_spacing = 2.5
        self.observations.policy.enable_corruption = False
        # no pushes
        self.events.base_external_force_torque = None
        self.events.push_robot = None
