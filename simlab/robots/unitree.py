"""Unitree robots (Isaac Lab's ``isaaclab_assets.robots.unitree``): the Go2 quadruped."""

import os

import simlab.sim as sim_utils
from simlab.actuators import DCMotorCfg
from simlab.assets import ArticulationCfg

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
