"""Unitree robots (Isaac Lab's ``isaaclab_assets.robots.unitree``): the Go2 quadruped, the H1 and G1
humanoids (Isaac Lab's actuator groups and gains) and the 29-DoF G1 of the motion-tracking tasks
(mjlab's motor model)."""

import math
import os

import simlab.sim as sim_utils
from simlab.actuators import ActuatorNetMLPCfg, DCMotorCfg, ImplicitActuatorCfg
from simlab.assets import ArticulationCfg
from simlab.utils.assets import ISAACLAB_NUCLEUS_DIR

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

UNITREE_GO2_CFG = ArticulationCfg(
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "unitree_go2.xml"),
        # PhysX's solver settings, as Isaac Lab's config has them (MuJoCo's solver is sim.mujoco)
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(
            solver_position_iteration_count=4, solver_velocity_iteration_count=0
        ),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 0.4),
        joint_pos={
            ".*L_hip_joint": 0.1,
            ".*R_hip_joint": -0.1,
            "F[L,R]_thigh_joint": 0.8,
            "R[L,R]_thigh_joint": 1.0,
            ".*_calf_joint": -1.5,
        },
        joint_vel={".*": 0.0},
    ),
    soft_joint_pos_limit_factor=0.9,
    actuators={
        "base_legs": DCMotorCfg(
            joint_names_expr=[".*_hip_joint", ".*_thigh_joint", ".*_calf_joint"],
            effort_limit=23.5,
            saturation_effort=23.5,
            velocity_limit=30.0,
            stiffness=25.0,
            damping=0.5,
            friction=0.0,
        ),
    },
)
"""Unitree Go2 with DC-motor legs (Isaac Lab's gains and limits: kp 25, kd 0.5, 23.5 N m, 30 rad/s)."""


# Isaac Lab starts Go1 and A1 in the default pose of Go2 (above).
_UNITREE_QUADRUPED_POSE = {
    ".*L_hip_joint": 0.1,
    ".*R_hip_joint": -0.1,
    "F[L,R]_thigh_joint": 0.8,
    "R[L,R]_thigh_joint": 1.0,
    ".*_calf_joint": -1.5,
}

GO1_DC_ACTUATOR_CFG = DCMotorCfg(
    joint_names_expr=[".*_hip_joint", ".*_thigh_joint", ".*_calf_joint"],
    effort_limit=23.7,
    saturation_effort=23.7,
    velocity_limit=30.0,
    stiffness=25.0,
    damping=0.5,
    friction=0.0,
)
"""Go1's motors as a DC motor: the limits of Isaac Lab's ``GO1_ACTUATOR_CFG`` (23.7 N m, 30 rad/s, from
Unitree's spec sheet) with the PD gains of Isaac Lab's Go2 and A1 (kp 25, kd 0.5). Isaac Lab drives Go1
with an MLP actuator network (walk-these-ways' ``unitree_go1.pt``), a trained file simlab does not ship."""

GO1_ACTUATOR_CFG = ActuatorNetMLPCfg(
    joint_names_expr=[".*_hip_joint", ".*_thigh_joint", ".*_calf_joint"],
    network_file=f"{ISAACLAB_NUCLEUS_DIR}/ActuatorNets/Unitree/unitree_go1.pt",
    pos_scale=-1.0,
    vel_scale=1.0,
    torque_scale=1.0,
    input_order="pos_vel",
    input_idx=[0, 1, 2],
    effort_limit=23.7,
    velocity_limit=30.0,
    saturation_effort=23.7,
)
"""Isaac Lab's Go1 MLP actuator config (its inputs, scales and limits). Its network path names simlab's
``simlab/actuators/nets/unitree_go1_mlp.pt``: an MLP of the same inputs fitted here to
``GO1_DC_ACTUATOR_CFG`` with a 2-physics-step delay (docs/actuators.md), not walk-these-ways' network."""

UNITREE_GO1_CFG = ArticulationCfg(
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "unitree_go1.xml"),
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(
            solver_position_iteration_count=4, solver_velocity_iteration_count=0
        ),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 0.4), joint_pos=dict(_UNITREE_QUADRUPED_POSE), joint_vel={".*": 0.0}
    ),
    soft_joint_pos_limit_factor=0.9,
    actuators={"base_legs": GO1_ACTUATOR_CFG},
)
"""Unitree Go1 (base body ``trunk``, as Isaac Lab's) driven as Isaac Lab drives it, by the MLP actuator
network config ``GO1_ACTUATOR_CFG`` (simlab's network: the DC motor ``GO1_DC_ACTUATOR_CFG`` with a
2-step delay). Under its default targets it stands at 0.28 m (0.28 m with the DC motor itself)."""

UNITREE_A1_CFG = ArticulationCfg(
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "unitree_a1.xml"),
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(
            solver_position_iteration_count=4, solver_velocity_iteration_count=0
        ),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 0.42), joint_pos=dict(_UNITREE_QUADRUPED_POSE), joint_vel={".*": 0.0}
    ),
    soft_joint_pos_limit_factor=0.9,
    actuators={
        "base_legs": DCMotorCfg(
            joint_names_expr=[".*_hip_joint", ".*_thigh_joint", ".*_calf_joint"],
            effort_limit=33.5,
            saturation_effort=33.5,
            velocity_limit=21.0,
            stiffness=25.0,
            damping=0.5,
            friction=0.0,
        ),
    },
)
"""Unitree A1 (base body ``trunk``) with DC-motor legs (Isaac Lab's gains and limits: kp 25, kd 0.5,
33.5 N m, 21 rad/s, from Trossen Robotics' A1 specifications)."""


H1_CFG = ArticulationCfg(
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "unitree_h1.xml"),
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(
            enabled_self_collisions=False, solver_position_iteration_count=4, solver_velocity_iteration_count=4
        ),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 1.05),
        joint_pos={
            ".*_hip_yaw": 0.0,
            ".*_hip_roll": 0.0,
            ".*_hip_pitch": -0.28,  # -16 degrees
            ".*_knee": 0.79,  # 45 degrees
            ".*_ankle": -0.52,  # -30 degrees
            "torso": 0.0,
            ".*_shoulder_pitch": 0.28,
            ".*_shoulder_roll": 0.0,
            ".*_shoulder_yaw": 0.0,
            ".*_elbow": 0.52,
        },
        joint_vel={".*": 0.0},
    ),
    soft_joint_pos_limit_factor=0.9,
    actuators={
        "legs": ImplicitActuatorCfg(
            joint_names_expr=[".*_hip_yaw", ".*_hip_roll", ".*_hip_pitch", ".*_knee", "torso"],
            effort_limit_sim=300.0,
            stiffness={
                ".*_hip_yaw": 150.0,
                ".*_hip_roll": 150.0,
                ".*_hip_pitch": 200.0,
                ".*_knee": 200.0,
                "torso": 200.0,
            },
            damping=5.0,
        ),
        "feet": ImplicitActuatorCfg(joint_names_expr=[".*_ankle"], effort_limit_sim=100.0, stiffness=20.0, damping=4.0),
        "arms": ImplicitActuatorCfg(
            joint_names_expr=[".*_shoulder_pitch", ".*_shoulder_roll", ".*_shoulder_yaw", ".*_elbow"],
            effort_limit_sim=300.0,
            stiffness=40.0,
            damping=10.0,
        ),
    },
)
"""Unitree H1 (19 joints) with Isaac Lab's implicit PD groups: legs and torso kp 150-200 / kd 5 (300 N m),
ankles kp 20 / kd 4 (100 N m), arms kp 40 / kd 10 (300 N m)."""

H1_MINIMAL_CFG = H1_CFG.copy()
"""H1 for the velocity tasks. Isaac Lab's drops most collision meshes; simlab's model has only
primitives to begin with, so this is the same robot as ``H1_CFG``."""


_G1_HAND_JOINTS = [f".*_{finger}_joint" for finger in ("five", "three", "six", "four", "zero", "one", "two")]

G1_CFG = ArticulationCfg(
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "unitree_g1.xml"),
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(
            enabled_self_collisions=False, solver_position_iteration_count=8, solver_velocity_iteration_count=4
        ),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 0.74),
        joint_pos={
            ".*_hip_pitch_joint": -0.20,
            ".*_knee_joint": 0.42,
            ".*_ankle_pitch_joint": -0.23,
            ".*_elbow_pitch_joint": 0.87,
            "left_shoulder_roll_joint": 0.16,
            "left_shoulder_pitch_joint": 0.35,
            "right_shoulder_roll_joint": -0.16,
            "right_shoulder_pitch_joint": 0.35,
            "left_one_joint": 1.0,
            "right_one_joint": -1.0,
            "left_two_joint": 0.52,
            "right_two_joint": -0.52,
        },
        joint_vel={".*": 0.0},
    ),
    soft_joint_pos_limit_factor=0.9,
    actuators={
        "legs": ImplicitActuatorCfg(
            joint_names_expr=[
                ".*_hip_yaw_joint",
                ".*_hip_roll_joint",
                ".*_hip_pitch_joint",
                ".*_knee_joint",
                "torso_joint",
            ],
            effort_limit_sim=300.0,
            stiffness={
                ".*_hip_yaw_joint": 150.0,
                ".*_hip_roll_joint": 150.0,
                ".*_hip_pitch_joint": 200.0,
                ".*_knee_joint": 200.0,
                "torso_joint": 200.0,
            },
            damping=5.0,
            armature=0.01,
        ),
        "feet": ImplicitActuatorCfg(
            joint_names_expr=[".*_ankle_pitch_joint", ".*_ankle_roll_joint"],
            effort_limit_sim=20.0,
            stiffness=20.0,
            damping=2.0,
            armature=0.01,
        ),
        "arms": ImplicitActuatorCfg(
            joint_names_expr=[
                ".*_shoulder_pitch_joint",
                ".*_shoulder_roll_joint",
                ".*_shoulder_yaw_joint",
                ".*_elbow_pitch_joint",
                ".*_elbow_roll_joint",
                *_G1_HAND_JOINTS,
            ],
            effort_limit_sim=300.0,
            stiffness=40.0,
            damping=10.0,
            armature={".*_shoulder_.*": 0.01, ".*_elbow_.*": 0.01, **{name: 0.001 for name in _G1_HAND_JOINTS}},
        ),
    },
)
"""Unitree G1 with hands (37 joints) and Isaac Lab's implicit PD groups: legs and torso kp 150-200 / kd 5
(300 N m), ankles kp 20 / kd 2 (20 N m), arms and hands kp 40 / kd 10 (300 N m); armature 0.01
(0.001 for the fingers)."""

G1_MINIMAL_CFG = G1_CFG.copy()
"""G1 for the velocity tasks. Isaac Lab's drops most collision meshes; simlab's model has only
primitives to begin with, so this is the same robot as ``G1_CFG``."""


# The 29-DoF G1's motors (Unitree's rotor inertias and gear ratios, reflected through the gearbox, as
# mjlab's G1 computes them): armature [kg m^2], effort limit [N m], velocity limit [rad/s].
# Ankles and waist roll/pitch are two 5020 through a linkage: twice the armature and torque.
_G1_MOTORS = {
    "7520_14": (0.010178, 88.0, 32.0, [".*_hip_pitch_joint", ".*_hip_yaw_joint", "waist_yaw_joint"]),
    "7520_22": (0.025102, 139.0, 20.0, [".*_hip_roll_joint", ".*_knee_joint"]),
    "5020": (
        0.003610,
        25.0,
        37.0,
        [
            ".*_shoulder_pitch_joint",
            ".*_shoulder_roll_joint",
            ".*_shoulder_yaw_joint",
            ".*_elbow_joint",
            ".*_wrist_roll_joint",
        ],
    ),
    "4010": (0.00425, 5.0, 22.0, [".*_wrist_pitch_joint", ".*_wrist_yaw_joint"]),
    "waist": (0.007219, 50.0, 37.0, ["waist_pitch_joint", "waist_roll_joint"]),
    "ankle": (0.007219, 50.0, 37.0, [".*_ankle_pitch_joint", ".*_ankle_roll_joint"]),
}
_G1_NATURAL_FREQ = 10.0 * 2.0 * math.pi  # 10 Hz
_G1_DAMPING_RATIO = 2.0


def _g1_motor_group(armature: float, effort: float, velocity: float, joints: list[str]) -> ImplicitActuatorCfg:
    # the velocity limit is the motor's, for reference: mjlab does not enforce it, nor does simlab here
    # kp and kd put each joint's reflected inertia at a 10 Hz, over-damped (ratio 2) second-order response
    return ImplicitActuatorCfg(
        joint_names_expr=joints,
        effort_limit_sim=effort,
        stiffness=armature * _G1_NATURAL_FREQ**2,
        damping=2.0 * _G1_DAMPING_RATIO * armature * _G1_NATURAL_FREQ,
        armature=armature,
    )


G1_29DOF_CFG = ArticulationCfg(
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "unitree_g1_29dof.xml"),
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(
            enabled_self_collisions=False, solver_position_iteration_count=8, solver_velocity_iteration_count=4
        ),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 0.76),
        joint_pos={
            ".*_hip_pitch_joint": -0.312,
            ".*_knee_joint": 0.669,
            ".*_ankle_pitch_joint": -0.363,
            ".*_elbow_joint": 0.6,
            "left_shoulder_roll_joint": 0.2,
            "left_shoulder_pitch_joint": 0.2,
            "right_shoulder_roll_joint": -0.2,
            "right_shoulder_pitch_joint": 0.2,
        },
        joint_vel={".*": 0.0},
    ),
    soft_joint_pos_limit_factor=0.9,
    actuators={name: _g1_motor_group(*motor) for name, motor in _G1_MOTORS.items()},
)
"""Unitree G1 29-DoF (no hands), the robot of mjlab's and Isaac Lab's motion-tracking tasks, with
mjlab's motor model: each joint's armature is its motor's reflected inertia, the PD gains give it a
10 Hz response with damping ratio 2, and the effort limits are the motors' (88, 139, 25, 5 N m; 50
for the linkage-driven ankles and waist). Starts in mjlab's knees-bent pose."""

G1_29DOF_ACTION_SCALE: dict[str, float] = {
    joint: 0.25 * effort / (armature * _G1_NATURAL_FREQ**2)
    for armature, effort, _, joints in _G1_MOTORS.values()
    for joint in joints
}
"""Per-joint action scale of the tracking tasks (mjlab's): a quarter of the effort limit over the stiffness."""


# The hand G1's body joints are driven by the same motors as the 29-DoF G1's (its torso joint is the
# waist yaw; its elbow pitch and roll are the elbow and wrist roll 5020s); the hands keep Isaac Lab's group.
_G1_HAND_VERSION_MOTORS = {
    "7520_14": (*_G1_MOTORS["7520_14"][:3], [".*_hip_pitch_joint", ".*_hip_yaw_joint", "torso_joint"]),
    "7520_22": _G1_MOTORS["7520_22"],
    "5020": (*_G1_MOTORS["5020"][:3], [".*_shoulder_.*_joint", ".*_elbow_pitch_joint", ".*_elbow_roll_joint"]),
    "ankle": _G1_MOTORS["ankle"],
}

G1_MOTOR_MODEL_CFG = G1_CFG.copy()
G1_MOTOR_MODEL_CFG.actuators = {
    **{name: _g1_motor_group(*motor) for name, motor in _G1_HAND_VERSION_MOTORS.items()},
    "hands": G1_CFG.actuators["arms"].replace(joint_names_expr=list(_G1_HAND_JOINTS), armature=0.001),
}
"""``G1_CFG`` (37 joints) with mjlab's motor model on its legs, torso and arms (each joint's armature its
motor's reflected inertia, PD gains for a 10 Hz response with damping ratio 2, the motors' effort
limits) and Isaac Lab's hand group: the model mjlab's G1 learns to walk with on MuJoCo. With Isaac Lab's
PhysX gains (hips kp 150-200 under a 300 N m limit: 100 N m per unit of action at its 0.5 scale, more
than the 88 N m hip motor) simlab's G1 flat task stood still through 806 iterations on an H100."""

G1_BODY_JOINTS = [
    f".*_{joint}_joint"
    for joint in ("hip_pitch", "hip_roll", "hip_yaw", "knee", "ankle_pitch", "ankle_roll")
    + ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow_pitch", "elbow_roll")
] + ["torso_joint"]
"""The hand G1's 23 joints that walk (legs, torso, arms): the velocity tasks' actions and joint observations."""

G1_MOTOR_MODEL_ACTION_SCALE: dict[str, float] = {
    joint: 0.25 * effort / (armature * _G1_NATURAL_FREQ**2)
    for armature, effort, _, joints in _G1_HAND_VERSION_MOTORS.values()
    for joint in joints
}
"""Per-joint action scale for ``G1_MOTOR_MODEL_CFG`` (mjlab's rule): a unit action asks a quarter of the
motor's effort limit from its stiffness."""
