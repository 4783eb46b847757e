"""The 28-joint humanoid of Isaac Lab's AMP tasks (``HUMANOID_28_CFG``): the joints and bodies its
motion files name (see ``simlab/robots/assets/humanoid_28.xml``)."""

import os

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

HUMANOID_28_CFG = ArticulationCfg(
    prim_path="{ENV_REGEX_NS}/Robot",
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "humanoid_28.xml"),
        # PhysX's solver settings, as Isaac Lab's config has them (MuJoCo's solver is sim.mujoco)
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(
            enabled_self_collisions=True, solver_position_iteration_count=4, solver_velocity_iteration_count=0
        ),
    ),
    init_state=ArticulationCfg.InitialStateCfg(pos=(0.0, 0.0, 0.8), joint_pos={".*": 0.0}),
    # Isaac Lab's: the gains left None keep the model's own (each joint's stiffness and damping in the MJCF)
    actuators={"body": ImplicitActuatorCfg(joint_names_expr=[".*"], stiffness=None, damping=None)},
)
"""Isaac Lab's 28-joint humanoid: pelvis spawned at 0.8 m, one implicit PD group with the model's gains."""
