"""The Universal Robots UR10 and UR10e arms (no gripper), as Isaac Lab configures them.

``UR10_CFG`` has Isaac Lab's joint names (``shoulder_pan_joint`` ... ``wrist_3_joint``), default pose
and its single actuator group ``arm`` (implicit PD, kp 800, kd 40, 87 N m). The model is
``simlab/robots/assets/universal_robots_ur10.xml`` (facts and sources in its header); the end
effector is the body ``ee_link``, whose x axis is the tool axis.

Isaac Lab's config also sets an armature of 1e-3 kg m^2; simlab keeps the model's 0.1 (the reflected
rotor inertia of a harmonic-drive joint, as the Franka model has). With 1e-3 the wrists (0.0006 kg m^2
of their own about wrist_3's axis) are driven at the 87 N m limit, where MuJoCo's implicit integrator
no longer damps the drive: a joint-position step from the default pose to another reached 1,100 rad/s
and did not settle (CPU, measured here); with 0.1 the wrists reach their targets within 0.35 s.
Under gravity the 87 N m limit leaves the PD a steady sag: a differential-IK target in the reach
command's range was missed by 3.5-4.9 cm with gravity on and by 0.01 mm with it off on the arm
(tests/test_ur10_reach.py).

``UR10e_CFG`` is Isaac Lab's UR10e (the deployed reach task's arm): the same joint names, its model
``simlab/robots/assets/universal_robots_ur10e.xml`` in the frames of Universal Robots' ROS 2
description, the end effector ``wrist_3_link`` (the tool flange, z out).
"""

import os

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

UR10_CFG = ArticulationCfg(
    prim_path="{ENV_REGEX_NS}/Robot",
    spawn=sim_utils.MjcfFileCfg(asset_path=os.path.join(ASSETS_DIR, "universal_robots_ur10.xml")),
    init_state=ArticulationCfg.InitialStateCfg(
        joint_pos={
            "shoulder_pan_joint": 0.0,
            "shoulder_lift_joint": -1.712,
            "elbow_joint": 1.712,
            "wrist_1_joint": 0.0,
            "wrist_2_joint": 0.0,
            "wrist_3_joint": 0.0,
        },
    ),
    actuators={
        "arm": ImplicitActuatorCfg(
            joint_names_expr=[".*"],
            effort_limit_sim=87.0,
            stiffness=800.0,
            damping=40.0,
            friction=1e-5,
        ),  # armature: the model's 0.1, not Isaac Lab's 1e-3 (see above)
    },
)
"""UR10 as in Isaac Lab: joint-space PD (kp 800, kd 40), 87 N m on every joint."""

UR10e_CFG = ArticulationCfg(
    prim_path="{ENV_REGEX_NS}/Robot",
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "universal_robots_ur10e.xml"),
        rigid_props=sim_utils.RigidBodyPropertiesCfg(disable_gravity=True),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        joint_pos={
            "shoulder_pan_joint": 3.141592653589793,
            "shoulder_lift_joint": -1.5707963267948966,
            "elbow_joint": 1.5707963267948966,
            "wrist_1_joint": -1.5707963267948966,
            "wrist_2_joint": -1.5707963267948966,
            "wrist_3_joint": 0.0,
        },
    ),
    # Isaac Lab's gains and armature; no torque limit in the config, as Isaac Lab's (see below)
    actuators={
        "shoulder": ImplicitActuatorCfg(
            joint_names_expr=["shoulder_.*"],
            stiffness=1320.0,
            damping=72.6636085,
            friction=0.0,
            armature=0.0,
        ),
        "elbow": ImplicitActuatorCfg(
            joint_names_expr=["elbow_joint"],
            stiffness=600.0,
            damping=34.64101615,
            friction=0.0,
            armature=0.0,
        ),
        "wrist": ImplicitActuatorCfg(
            joint_names_expr=["wrist_.*"],
            stiffness=216.0,
            damping=29.39387691,
            friction=0.0,
            armature=0.0,
        ),
    },
)
"""UR10e as in Isaac Lab: gravity off on the arm, the pan joint half a turn round and the tool pointing
down; joint-space PD per group (shoulders kp 1320 / kd 72.7, elbow 600 / 34.6, wrists 216 / 29.4), no
armature. The end effector is ``wrist_3_link``, the tool flange (z out).

Isaac Lab's config sets no torque limit (its USD's drives have theirs); simlab's drives have none either.
Capped at the datasheet's 330 / 150 / 56 N m, the wrists (0.0006 kg m^2 about wrist_3's axis, no
armature) are driven at the cap by random actions of the deployed reach task, where MuJoCo's implicit
integrator no longer damps the drive: wrist_3 reached 744 rad/s (CPU, 16 envs, measured here)."""
