"""The MuJoCo ant of Isaac Lab's Ant task: four legs of two hinges each, torso on a free joint."""

import os

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

ANT_CFG = ArticulationCfg(
    prim_path="{ENV_REGEX_NS}/Robot",
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "ant.xml"),
        # PhysX's solver settings, as Isaac Lab's config has them (MuJoCo's solver is sim.mujoco)
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(
            solver_position_iteration_count=4, solver_velocity_iteration_count=0
        ),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 0.5),
        joint_pos={
            ".*_leg": 0.0,
            "front_left_foot": 0.785398,  # 45 degrees
            "front_right_foot": -0.785398,
            "left_back_foot": -0.785398,
            "right_back_foot": 0.785398,
        },
    ),
    actuators={
        # Pure torque drives: the task writes gear * action as effort targets.
        "body": ImplicitActuatorCfg(
            joint_names_expr=[".*"], stiffness=0.0, damping=0.0, effort_limit_sim=30.0, friction=0.0001
        ),
    },
)
"""Ant as in Isaac Lab: spawned 0.5 m up, feet bent 45 deg, torque-only joints (30 N m limit)."""
