"""A kitchen base cabinet with two drawers and two doors, as Isaac Lab's Sektion cabinet prop.

``SEKTION_CABINET_CFG`` has the prop's joint names (``drawer_top_joint``, ``drawer_bottom_joint``,
``door_left_joint``, ``door_right_joint``), body names (``drawer_top``, ``drawer_handle_top``, ...)
and the weak drives Isaac Lab's cabinet tasks give it. The model is
``simlab/robots/assets/sektion_cabinet.xml`` (sizes and frame placement in its header); its base is
fixed where the config spawns it.
"""

import os

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

SEKTION_CABINET_CFG = ArticulationCfg(
    prim_path="{ENV_REGEX_NS}/Cabinet",
    spawn=sim_utils.MjcfFileCfg(asset_path=os.path.join(ASSETS_DIR, "sektion_cabinet.xml")),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 0.4),
        joint_pos={
            "door_left_joint": 0.0,
            "door_right_joint": 0.0,
            "drawer_bottom_joint": 0.0,
            "drawer_top_joint": 0.0,
        },
    ),
    actuators={
        # a spring towards closed (position target 0), as in Isaac Lab's cabinet tasks
        "drawers": ImplicitActuatorCfg(
            joint_names_expr=["drawer_top_joint", "drawer_bottom_joint"],
            effort_limit_sim=87.0,
            stiffness=10.0,
            damping=1.0,
        ),
        "doors": ImplicitActuatorCfg(
            joint_names_expr=["door_left_joint", "door_right_joint"], effort_limit_sim=87.0, stiffness=10.0, damping=2.5
        ),
    },
)
"""The cabinet standing on the floor at the env's origin, front towards +x, drawers and doors closed."""
