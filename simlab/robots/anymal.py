"""ANYbotics robots (Isaac Lab's ``isaaclab_assets.robots.anymal``): ANYmal-C."""

import os

import simlab.sim as sim_utils
from simlab.actuators import DCMotorCfg
from simlab.assets import ArticulationCfg

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

ANYDRIVE_3_SIMPLE_ACTUATOR_CFG = DCMotorCfg(
    joint_names_expr=[".*HAA", ".*HFE", ".*KFE"],
    saturation_effort=120.0,
    effort_limit=80.0,
    velocity_limit=7.5,
    stiffness={".*": 40.0},
    damping={".*": 5.0},
)
"""ANYdrive 3.x as a DC motor (Isaac Lab's simple actuator model)."""

ANYMAL_C_CFG = ArticulationCfg(
    spawn=sim_utils.MjcfFileCfg(asset_path=os.path.join(ASSETS_DIR, "anybotics_anymal_c.xml")),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 0.6),
        joint_pos={
            ".*HAA": 0.0,
            ".*F_HFE": 0.4,
            ".*H_HFE": -0.4,
            ".*F_KFE": -0.8,
            ".*H_KFE": 0.8,
        },
    ),
    actuators={"legs": ANYDRIVE_3_SIMPLE_ACTUATOR_CFG},
    soft_joint_pos_limit_factor=0.95,
)
"""ANYmal-C. Isaac Lab drives it with an LSTM actuator network (``ANYDRIVE_3_LSTM_ACTUATOR_CFG``),
a trained file simlab does not ship; here it has Isaac Lab's DC-motor ANYdrive model instead."""
