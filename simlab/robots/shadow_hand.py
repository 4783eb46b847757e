"""The Shadow Dexterous Hand from Shadow Robot, as Isaac Lab configures it (``isaaclab_assets.robots.shadow_hand``).

``SHADOW_HAND_CFG`` has Isaac Lab's joint names (``robot0_WRJ1`` .. ``robot0_THJ0``), its pose (palm
up at 0.5 m, the forearm along -y), gravity switched off on the hand, and one implicit actuator group
"fingers" over the 20 actuated joints with Isaac Lab's per-joint effort limits, stiffness and damping.
The four distal joints (``robot0_(FF|MF|RF|LF)J0``) have no actuator: the model couples each to its
finger's middle joint. The model is ``simlab/robots/assets/shadow_hand.xml`` (facts and sources in its header).
"""

import os

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

SHADOW_HAND_CFG = ArticulationCfg(
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "shadow_hand.xml"),
        activate_contact_sensors=False,
        rigid_props=sim_utils.RigidBodyPropertiesCfg(
            disable_gravity=True,
            retain_accelerations=True,
            max_depenetration_velocity=1000.0,
        ),
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(
            enabled_self_collisions=True,
            solver_position_iteration_count=8,
            solver_velocity_iteration_count=0,
            sleep_threshold=0.005,
            stabilization_threshold=0.0005,
        ),
        joint_drive_props=sim_utils.JointDrivePropertiesCfg(drive_type="force"),
        fixed_tendons_props=sim_utils.FixedTendonPropertiesCfg(limit_stiffness=30.0, damping=0.1),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 0.5),
        rot=(1.0, 0.0, 0.0, 0.0),
        joint_pos={".*": 0.0},
    ),
    actuators={
        "fingers": ImplicitActuatorCfg(
            joint_names_expr=["robot0_WR.*", "robot0_(FF|MF|RF|LF|TH)J(3|2|1)", "robot0_(LF|TH)J4", "robot0_THJ0"],
            effort_limit_sim={
                "robot0_WRJ1": 4.785,
                "robot0_WRJ0": 2.175,
                "robot0_(FF|MF|RF|LF)J1": 0.7245,
                "robot0_FFJ(3|2)": 0.9,
                "robot0_MFJ(3|2)": 0.9,
                "robot0_RFJ(3|2)": 0.9,
                "robot0_LFJ(4|3|2)": 0.9,
                "robot0_THJ4": 2.3722,
                "robot0_THJ3": 1.45,
                "robot0_THJ(2|1)": 0.99,
                "robot0_THJ0": 0.81,
            },
            stiffness={
                "robot0_WRJ.*": 5.0,
                "robot0_(FF|MF|RF|LF|TH)J(3|2|1)": 1.0,
                "robot0_(LF|TH)J4": 1.0,
                "robot0_THJ0": 1.0,
            },
            damping={
                "robot0_WRJ.*": 0.5,
                "robot0_(FF|MF|RF|LF|TH)J(3|2|1)": 0.1,
                "robot0_(LF|TH)J4": 0.1,
                "robot0_THJ0": 0.1,
            },
        ),
    },
    soft_joint_pos_limit_factor=1.0,
)
"""Shadow Hand as in Isaac Lab: palm up, implicit PD on the 20 actuated joints (wrist kp 5, fingers kp 1)."""

SHADOW_HAND_FINGERTIP_BODIES = [
    "robot0_ffdistal",
    "robot0_mfdistal",
    "robot0_rfdistal",
    "robot0_lfdistal",
    "robot0_thdistal",
]
"""The fingertip bodies Isaac Lab's in-hand tasks read (``fingertip_body_names``)."""

SHADOW_HAND_COUPLED_JOINTS = {f"robot0_{f}J0": f"robot0_{f}J1" for f in ("FF", "MF", "RF", "LF")}
"""Each distal joint and the middle joint it follows."""
