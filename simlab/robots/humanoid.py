"""The MuJoCo humanoid of Isaac Lab's Humanoid task: 21 hinge joints, torso on a free joint.

Joints are named like Isaac Lab's (``lower_waist:0``, ``right_thigh:1``, ...) but come in MuJoCo's
depth-first order; map anything per joint by name (see ``simlab/robots/assets/humanoid.xml``).
"""

import os

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

HUMANOID_GEARS = {
    "lower_waist:.*": 67.5,
    "pelvis": 67.5,
    ".*_upper_arm:.*": 67.5,
    ".*_lower_arm": 45.0,
    ".*_thigh:0": 45.0,
    ".*_thigh:1": 135.0,
    ".*_thigh:2": 45.0,
    ".*_shin": 90.0,
    ".*_foot:.*": 22.5,
}
"""Isaac Lab's gears of the humanoid [N m]: each joint's torque at action 1 in the torque-driven
tasks, i.e. the strength of its motor (the AMP task's drives are limited to them)."""

HUMANOID_CFG = ArticulationCfg(
    prim_path="{ENV_REGEX_NS}/Robot",
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "humanoid.xml"),
        # PhysX's solver settings, as Isaac Lab's config has them (MuJoCo's solver is sim.mujoco)
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(
            solver_position_iteration_count=4, solver_velocity_iteration_count=0
        ),
    ),
    init_state=ArticulationCfg.InitialStateCfg(pos=(0.0, 0.0, 1.34), joint_pos={".*": 0.0}),
    actuators={
        # Isaac Lab's gains: the joint springs/dampers of the MuJoCo model, as implicit PD drives
        # towards the default pose; the task adds its torques as effort targets on top.
        "body": ImplicitActuatorCfg(
            joint_names_expr=[".*"],
            stiffness={
                ".*_waist.*": 20.0,
                ".*_upper_arm.*": 10.0,
                "pelvis": 10.0,
                ".*_lower_arm": 2.0,
                ".*_thigh:0": 10.0,
                ".*_thigh:1": 20.0,
                ".*_thigh:2": 10.0,
                ".*_shin": 5.0,
                ".*_foot.*": 2.0,
            },
            damping={
                ".*_waist.*": 5.0,
                ".*_upper_arm.*": 5.0,
                "pelvis": 5.0,
                ".*_lower_arm": 1.0,
                ".*_thigh:0": 5.0,
                ".*_thigh:1": 5.0,
                ".*_thigh:2": 5.0,
                ".*_shin": 0.1,
                ".*_foot.*": 1.0,
            },
            velocity_limit_sim={".*": 100.0},
            armature={".*": 0.01},
            effort_limit_sim=150.0,
        ),
    },
)
"""Humanoid as in Isaac Lab: torso spawned at 1.34 m, implicit PD per joint group, 150 N m limit."""
