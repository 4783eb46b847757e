"""The Allegro Hand from Wonik Robotics, as Isaac Lab configures it (``isaaclab_assets.robots.allegro``).

``ALLEGRO_HAND_CFG`` has Isaac Lab's joint names (``<finger>_joint_0`` .. ``_3`` for the index,
middle, ring fingers and the thumb), its pose (palm up at 0.5 m, fingers along -y; the thumb's base
joint at 0.28 rad, the others at 0), gravity switched off on the hand, and one implicit actuator group
"fingers" with the gains Isaac Lab ships now (3.x): kp 1 N m/rad, kd 0.1, 0.5 N m, friction 1e-4 N m.
Isaac Lab 2.x (and IsaacGymEnvs) had kp 3 and friction 0.01; under MuJoCo that hand curls to the
mid-range targets of zero actions hard enough to throw the cube off the palm in 13 steps (direct task,
32 envs x 120 steps; docs/dexterous.md), where kp 1 keeps it for all 120.
Isaac Lab 3.x also sets armature 1e-4; the model keeps its 0.001 kg m^2 (IsaacGymEnvs' value): with
1e-4 the lighter fingers move faster and PPO's first noise, N(0, 1) actions, throws the cube off in
21 steps on average instead of 42. The model is ``simlab/robots/assets/allegro_hand.xml`` (facts and
sources in its header).
"""

import math
import os

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

ALLEGRO_HAND_CFG = ArticulationCfg(
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "allegro_hand.xml"),
        activate_contact_sensors=False,
        rigid_props=sim_utils.RigidBodyPropertiesCfg(
            disable_gravity=True,
            retain_accelerations=False,
            enable_gyroscopic_forces=False,
            angular_damping=0.01,
            max_linear_velocity=1000.0,
            max_angular_velocity=64 / math.pi * 180.0,
            max_depenetration_velocity=1000.0,
            max_contact_impulse=1e32,
        ),
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(
            enabled_self_collisions=True,
            solver_position_iteration_count=8,
            solver_velocity_iteration_count=0,
            sleep_threshold=0.005,
            stabilization_threshold=0.0005,
        ),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 0.5),
        rot=(0.257551, 0.283045, 0.683330, -0.621782),
        joint_pos={"^(?!thumb_joint_0).*": 0.0, "thumb_joint_0": 0.28},
    ),
    actuators={
        "fingers": ImplicitActuatorCfg(
            joint_names_expr=[".*"],
            effort_limit_sim=0.5,
            velocity_limit_sim=100.0,
            stiffness=1.0,
            damping=0.1,
            friction=1e-4,
        ),  # armature: the model's 0.001, not Isaac Lab 3.x's 1e-4 (see above)
    },
    soft_joint_pos_limit_factor=1.0,
)
"""Allegro Hand as in Isaac Lab: palm up, implicit PD (kp 1, kd 0.1) on all 16 joints, 0.5 N m."""

ALLEGRO_FINGERTIP_BODIES = ["index_link_3", "middle_link_3", "ring_link_3", "thumb_link_3"]
"""The fingertip bodies Isaac Lab's in-hand tasks read (``fingertip_body_names``)."""
