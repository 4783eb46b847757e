"""The cartpole: a cart on a 8 m rail (``slider_to_cart``) carrying a passive pole (``cart_to_pole``)."""

import os

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

CARTPOLE_CFG = ArticulationCfg(
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "cartpole.xml"),
        # PhysX's solver settings, as Isaac Lab's config has them (MuJoCo's solver is sim.mujoco)
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(
            solver_position_iteration_count=4, solver_velocity_iteration_count=0
        ),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 2.0), joint_pos={"slider_to_cart": 0.0, "cart_to_pole": 0.0}
    ),
    actuators={
        "cart_actuator": ImplicitActuatorCfg(
            joint_names_expr=["slider_to_cart"], effort_limit_sim=400.0, stiffness=0.0, damping=10.0
        ),
        "pole_actuator": ImplicitActuatorCfg(
            joint_names_expr=["cart_to_pole"], effort_limit_sim=400.0, stiffness=0.0, damping=0.0
        ),
    },
)
"""Cartpole as in Isaac Lab: spawned 2 m up, the slider damped (10 N s/m, 400 N limit), the pole free."""
