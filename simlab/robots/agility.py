"""Agility Robotics Digit V4 (Isaac Lab's ``isaaclab_assets.robots.agility``): a humanoid whose legs
close three loops each (the achilles rod and the two toe rods), held by equality constraints in the
MJCF (``agility_digit.xml``, which says where its numbers come from)."""

import math
import os

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

LEG_JOINT_NAMES = [
    ".*_hip_roll",
    ".*_hip_yaw",
    ".*_hip_pitch",
    ".*_knee",
    ".*_toe_a",
    ".*_toe_b",
]
"""The leg motors (Isaac Lab's list): the tarsus, toe pitch and toe roll are passive, moved by the rods."""

ARM_JOINT_NAMES = [".*_arm_.*"]

# Isaac Lab starts Digit at digit_v4.usd's zero pose, 1.05 m up. The zero pose of Agility's model, where
# the rods close, has the legs splayed (the feet 0.8 m apart): the hip roll housings sit 21.5 degrees
# out. The legs start instead in Agility's standing pose (hip roll 0.365, pitch 0.317, knee 0.358 rad,
# as Legged Lab's DIGIT_CFG gives it), the toe motors turned so that the soles lie flat, and the
# passive joints where the rods then hold them; the arms at zero (hanging), as Isaac Lab's.
DIGIT_HIP_ROLL = 0.3652
DIGIT_HIP_YAW = -0.0066
DIGIT_HIP_PITCH = 0.3169
DIGIT_KNEE = 0.3579
DIGIT_TARSUS = -0.3579
"""Where the achilles rod holds the tarsus at ``DIGIT_KNEE`` [rad] (left leg; the right mirrors)."""
DIGIT_TOE_A = -0.1998
DIGIT_TOE_B = 0.1924
DIGIT_TOE_PITCH = 0.2035
"""Where the toe rods hold the foot at ``DIGIT_TOE_A`` and ``DIGIT_TOE_B``: sole flat [rad]."""
DIGIT_TOE_ROLL = -0.0116


def _legs() -> dict[str, float]:
    pose = {
        "hip_roll": DIGIT_HIP_ROLL,
        "hip_yaw": DIGIT_HIP_YAW,
        "hip_pitch": DIGIT_HIP_PITCH,
        "knee": DIGIT_KNEE,
        "tarsus": DIGIT_TARSUS,
        "toe_a": DIGIT_TOE_A,
        "toe_b": DIGIT_TOE_B,
        "toe_pitch": DIGIT_TOE_PITCH,
        "toe_roll": DIGIT_TOE_ROLL,
    }
    # the right leg's frames mirror the left's: every angle changes sign
    return {f"{side}_leg_{joint}": sign * q for side, sign in (("left", 1), ("right", -1)) for joint, q in pose.items()}


DIGIT_V4_CFG = ArticulationCfg(
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "agility_digit.xml"),
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(enabled_self_collisions=True),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 1.05),  # Isaac Lab's; the soles 13 mm above the ground
        joint_pos={**_legs(), ".*_arm_.*": 0.0},
        joint_vel={".*": 0.0},
    ),
    soft_joint_pos_limit_factor=0.9,
    actuators={
        # Isaac Lab's one group, its gains read from digit_v4.usd (stiffness=None), which simlab cannot
        # read: these are Legged Lab's Digit gains (its DIGIT_CFG, less the motor damping it adds to kd);
        # the wrists, which Digit v3 lacks, get the toe motors'. Effort limits: Agility's v3 model (its
        # motors' gear times their current limit). The passive joints are in no group.
        "all": ImplicitActuatorCfg(
            joint_names_expr=LEG_JOINT_NAMES + ARM_JOINT_NAMES,
            effort_limit_sim={
                ".*_hip_roll": 112.0,
                ".*_hip_yaw": 70.0,
                ".*_hip_pitch": 200.0,
                ".*_knee": 200.0,
                ".*_toe_[ab]": 45.0,
                ".*_shoulder_(roll|pitch)": 112.0,
                ".*_shoulder_yaw": 70.0,
                ".*_elbow": 112.0,
                ".*_wrist_.*": 45.0,
            },
            stiffness={
                ".*_hip_(roll|yaw)": 100.0,
                ".*_hip_pitch": 200.0,
                ".*_knee": 200.0,
                ".*_toe_[ab]": 20.0,
                ".*_shoulder_(roll|pitch)": 150.0,
                ".*_shoulder_yaw": 100.0,
                ".*_elbow": 100.0,
                ".*_wrist_.*": 20.0,
            },
            damping={".*_toe_[ab]": 1.0, ".*_wrist_.*": 1.0, ".*_(hip|knee|shoulder|elbow).*": 5.0},
        ),
    },
)
"""Digit V4 (32 joints, Isaac Lab's names; 26 driven: 12 leg motors, 14 arm joints). Passive, set by
the rods: tarsus, toe pitch, toe roll. Starts in Agility's standing pose (see above), 1.05 m up."""


# Agility's motors as digit-v3's MJCF gives them: each joint's armature (the rotor's inertia reflected
# through its gearbox, also in agility_digit.xml) [kg m^2] and DIGIT_V4_CFG's effort limit [N m].
DIGIT_MOTORS: dict[str, tuple[float, float]] = {
    ".*_hip_roll": (0.1728, 112.0),
    ".*_hip_yaw": (0.0675, 70.0),
    ".*_hip_pitch": (0.120576, 200.0),
    ".*_knee": (0.120576, 200.0),
    ".*_toe_[ab]": (0.035, 45.0),
    ".*_shoulder_(roll|pitch)": (0.1728, 112.0),
    ".*_shoulder_yaw": (0.0675, 70.0),
    ".*_elbow": (0.1728, 112.0),
    ".*_wrist_.*": (0.035, 45.0),
}
DIGIT_NATURAL_FREQ = 10.0 * 2.0 * math.pi  # 10 Hz, mjlab's rule for its MuJoCo robots
DIGIT_DAMPING_RATIO = 2.0

DIGIT_V4_MOTOR_MODEL_CFG = DIGIT_V4_CFG.replace(
    actuators={
        "all": ImplicitActuatorCfg(
            joint_names_expr=LEG_JOINT_NAMES + ARM_JOINT_NAMES,
            effort_limit_sim={joint: effort for joint, (_, effort) in DIGIT_MOTORS.items()},
            stiffness={joint: armature * DIGIT_NATURAL_FREQ**2 for joint, (armature, _) in DIGIT_MOTORS.items()},
            damping={
                joint: 2.0 * DIGIT_DAMPING_RATIO * armature * DIGIT_NATURAL_FREQ
                for joint, (armature, _) in DIGIT_MOTORS.items()
            },
        ),
    },
)
"""``DIGIT_V4_CFG`` with mjlab's motor model, the gains the velocity tasks use: PD gains that put each
motor's reflected inertia (the MJCF's armature) at a 10 Hz, over-damped (ratio 2) response: hip roll,
shoulders and elbows kp 682 / kd 43, hip pitch and knee 476 / 30, hip and shoulder yaw 266 / 17, toe
motors and wrists 138 / 9. With ``DIGIT_V4_CFG``'s kp 200 / kd 5 and the targets at the default pose the
knees give 0.6 rad under the robot's weight within 0.4 s and it falls in 0.7 s; with these they give
0.13 rad and it stands about 1.3 s before tipping (balancing is the policy's job)."""

DIGIT_V4_MOTOR_MODEL_ACTION_SCALE: dict[str, float] = {
    joint: 0.25 * effort / (armature * DIGIT_NATURAL_FREQ**2) for joint, (armature, effort) in DIGIT_MOTORS.items()
}
"""Per-joint action scale for ``DIGIT_V4_MOTOR_MODEL_CFG`` (mjlab's rule, as the G1's): a unit action asks a
quarter of the motor's effort limit from its stiffness (hip pitch and knee 0.105 rad, hip roll 0.041)."""
