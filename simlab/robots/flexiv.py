"""The Flexiv Rizon 4s arm (no gripper), as Isaac Lab configures it for its deployed reach task.

``FLEXIV_RIZON4S_CFG`` has Isaac Lab's joint names (``joint1`` ... ``joint7``), default pose, base turned
half a turn about z, gravity off on the arm, and its three implicit actuator groups with the datasheet's
torques and speeds: shoulder (joints 1-2: kp 6000, kd 108.5, 123 N m, 2.094 rad/s), elbow (3-4: 4200,
90.7, 64 N m, 2.443 rad/s), wrist (5-7: 1500, 54.2, 39 N m, 4.887 rad/s). The model is
``simlab/robots/assets/flexiv_rizon4s.xml`` (facts and sources in its header); the end effector is the
body ``flange``, its z axis the tool axis.

Isaac Lab sets no armature; simlab gives every joint 0.1 kg m^2 (the reflected rotor inertia of a
harmonic-drive joint, as simlab's UR10 and Franka models have). The wrist gain meets the 39 N m cap at
0.026 rad of error, under half an action of the deployed reach (0.0625 rad per unit), and at the cap
MuJoCo's implicit integrator no longer damps the drive: under random actions of that task (16 envs,
6 s, CPU) the joints reached 190 rad/s without armature and 11 rad/s with it.
"""

import os

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

FLEXIV_RIZON4S_CFG = ArticulationCfg(
    prim_path="{ENV_REGEX_NS}/Robot",
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "flexiv_rizon4s.xml"),
        rigid_props=sim_utils.RigidBodyPropertiesCfg(disable_gravity=True),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        joint_pos={
            "joint1": 0.0,
            "joint2": -0.698,
            "joint3": 0.0,
            "joint4": 1.571,
            "joint5": 0.0,
            "joint6": 0.698,
            "joint7": 0.0,
        },
        pos=(0.0, 0.0, 0.0),
        rot=(0.0, 0.0, 0.0, 1.0),
    ),
    actuators={
        "shoulder": ImplicitActuatorCfg(
            joint_names_expr=["joint[1-2]"],
            effort_limit_sim=123.0,
            velocity_limit_sim=2.094,
            stiffness=6000.0,
            damping=108.5,
            friction=0.0,
            armature=0.1,
        ),
        "elbow": ImplicitActuatorCfg(
            joint_names_expr=["joint[3-4]"],
            effort_limit_sim=64.0,
            velocity_limit_sim=2.443,
            stiffness=4200.0,
            damping=90.7,
            friction=0.0,
            armature=0.1,
        ),
        "wrist": ImplicitActuatorCfg(
            joint_names_expr=["joint[5-7]"],
            effort_limit_sim=39.0,
            velocity_limit_sim=4.887,
            stiffness=1500.0,
            damping=54.2,
            friction=0.0,
            armature=0.1,
        ),
    },
)
"""Rizon 4s as in Isaac Lab (its deployed reach task's arm), but for an armature of 0.1 kg m^2 (above)."""
