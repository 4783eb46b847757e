"""The Crazyflie 2.x of Isaac Lab's quadcopter task: a 27 g body on a free joint, four spinning propellers."""

import os

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

CRAZYFLIE_CFG = ArticulationCfg(
    prim_path="{ENV_REGEX_NS}/Robot",
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "crazyflie.xml"),
        # Isaac Lab's rigid-body settings. enable_gyroscopic_forces matters: it makes the scene integrate
        # with MuJoCo's "implicit" integrator, without which an exploring policy's 700 rad/s^2 moments
        # spin the 27 g drone up without bound in 10 ms steps (and training does not learn).
        rigid_props=sim_utils.RigidBodyPropertiesCfg(
            disable_gravity=False, max_depenetration_velocity=10.0, enable_gyroscopic_forces=True
        ),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 0.5),
        joint_pos={".*": 0.0},
        # Propellers spin in opposite pairs (their angular momenta cancel); they carry no thrust.
        joint_vel={"m1_joint": 200.0, "m2_joint": -200.0, "m3_joint": 200.0, "m4_joint": -200.0},
    ),
    actuators={
        # The propeller hinges are free: the task flies the drone with an external wrench on "body".
        "dummy": ImplicitActuatorCfg(joint_names_expr=[".*"], stiffness=0.0, damping=0.0),
    },
)
"""Crazyflie as in Isaac Lab: spawned 0.5 m up, propellers spinning at +-200 rad/s, no joint drives."""
