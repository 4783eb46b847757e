"""Agility Robotics Cassie (Isaac Lab's ``isaaclab_assets.robots.cassie``): a biped whose tarsus follows
the knee through the achilles rod, a closed loop held by an equality constraint in the MJCF."""

import os

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

# Isaac Lab's default pose (hip flexion 1.0, knee -1.8, tarsus 1.57, toe -1.57) comes from a URDF without
# the achilles rod. Here the rod sets the tarsus from the knee (2.02 at -1.8), and that crouch puts the
# feet 11 cm ahead of the centre of mass. The sagittal joints start instead in menagerie's standing
# keyframe ("home"), the tarsus where the rod holds it; hip abduction and rotation are Isaac Lab's.
CASSIE_HIP_FLEXION = 0.4973
CASSIE_KNEE = -1.1997
CASSIE_TARSUS = 1.4211
"""The tarsus angle (``ankle_joint``) at which the achilles rod sits at ``CASSIE_KNEE`` [rad]."""
CASSIE_TOE = -1.5968

CASSIE_CFG = ArticulationCfg(
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "agility_cassie.xml"),
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(enabled_self_collisions=True),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 1.01),  # the soles 1 cm above the ground (Isaac Lab: 0.9)
        joint_pos={
            "hip_abduction_left": 0.1,
            "hip_rotation_left": 0.0,
            "hip_flexion_left": CASSIE_HIP_FLEXION,
            "thigh_joint_left": CASSIE_KNEE,
            "ankle_joint_left": CASSIE_TARSUS,
            "toe_joint_left": CASSIE_TOE,
            "hip_abduction_right": -0.1,
            "hip_rotation_right": 0.0,
            "hip_flexion_right": CASSIE_HIP_FLEXION,
            "thigh_joint_right": CASSIE_KNEE,
            "ankle_joint_right": CASSIE_TARSUS,
            "toe_joint_right": CASSIE_TOE,
        },
        joint_vel={".*": 0.0},
    ),
    soft_joint_pos_limit_factor=0.9,
    actuators={
        # Isaac Lab's groups and gains, less the ankle: its drive would fight the achilles rod, which sets
        # the tarsus from the knee (Cassie has no tarsus motor; Isaac Lab's URDF has no rod).
        "legs": ImplicitActuatorCfg(
            joint_names_expr=["hip_.*", "thigh_.*"],
            effort_limit_sim=200.0,
            stiffness={
                "hip_abduction.*": 100.0,
                "hip_rotation.*": 100.0,
                "hip_flexion.*": 200.0,
                "thigh_joint.*": 200.0,
            },
            damping={"hip_abduction.*": 3.0, "hip_rotation.*": 3.0, "hip_flexion.*": 6.0, "thigh_joint.*": 6.0},
            armature=1e-3,
        ),
        "toes": ImplicitActuatorCfg(
            joint_names_expr=["toe_.*"],
            effort_limit_sim=20.0,
            stiffness={"toe_joint.*": 20.0},
            damping={"toe_joint.*": 1.0},
            armature=1e-3,
        ),
    },
)
"""Cassie (12 joints, Isaac Lab's names and gains; 10 driven): hips and knees kp 100-200 / kd 3-6 (200 N m),
toes kp 20 / kd 1 (20 N m). The tarsus (``ankle_joint``) is passive, set by the knee through the achilles
rod. Starts in menagerie's standing pose (see above), 1.01 m up."""
