"""A cart on a rail carrying a pole and, on top of it, a pendulum (Isaac Lab's cart double pendulum).

Joints: ``slider_to_cart`` (rail along y, +-4 m), ``cart_to_pole`` and ``pole_to_pendulum`` (free
revolute joints, 0 = upright).
"""

import os

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

CART_DOUBLE_PENDULUM_CFG = ArticulationCfg(
    spawn=sim_utils.MjcfFileCfg(asset_path=os.path.join(ASSETS_DIR, "cart_double_pendulum.xml")),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 2.0), joint_pos={"slider_to_cart": 0.0, "cart_to_pole": 0.0, "pole_to_pendulum": 0.0}
    ),
    actuators={
        "cart_actuator": ImplicitActuatorCfg(
            joint_names_expr=["slider_to_cart"], effort_limit_sim=400.0, stiffness=0.0, damping=10.0
        ),
        "pole_actuator": ImplicitActuatorCfg(
            joint_names_expr=["cart_to_pole"], effort_limit_sim=400.0, stiffness=0.0, damping=0.0
        ),
        "pendulum_actuator": ImplicitActuatorCfg(
            joint_names_expr=["pole_to_pendulum"], effort_limit_sim=400.0, stiffness=0.0, damping=0.0
        ),
    },
)
"""Cart double pendulum as in Isaac Lab: 2 m up, the slider damped (10 N s/m), 400 N (m) limits."""
