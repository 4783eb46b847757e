"""Enactic OpenArm v1.0 (Isaac Lab's ``isaaclab_assets.robots.openarm``): one arm or two arms on a body,
each a 7-joint arm with a parallel gripper.

``OPENARM_UNI_CFG`` (one arm, ``openarm_joint1`` ... ``openarm_joint7``, ``openarm_finger_joint1``/``2``)
and ``OPENARM_BI_CFG`` (two, ``openarm_left_*`` and ``openarm_right_*``) carry Isaac Lab's settings: the
arm as one implicit-PD group (kp 80, kd 4; torque limits 40 / 27 / 7 N m and speed limits 2.175 / 2.61
rad/s for joints 1-2 / 3-4 / 5-7, the Damiao motors' ratings), the gripper as another (kp 2000, kd 100,
0.2 m/s), self-collisions off, gravity on; the one arm starts in its reach pose (joint1 1.57, joint3
-1.57, joint4 1.57, the hand pointing forward), the two arms hanging (all zero). The ``_HIGH_PD`` configs
are Isaac Lab's for task-space control: gravity off, arm kp 400, kd 80.

The models are ``simlab/robots/assets/enactic_openarm.xml`` and ``enactic_openarm_bimanual.xml`` (facts
and sources in their headers): Enactic's published kinematics, joint ranges and inertials, primitive
geometry, and an armature of 0.01 kg m^2 on the arm joints that Isaac Lab's config does not set (without
it, the 7 N m wrists chatter at their torque cap: the model's header says what was measured). The end
effectors are the bodies ``openarm_hand`` / ``openarm_{left,right}_hand`` (z along the fingers).
"""

import os

import simlab.sim as sim_utils
from simlab.actuators import ImplicitActuatorCfg
from simlab.assets import ArticulationCfg

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")


def _spawn(model: str) -> sim_utils.MjcfFileCfg:
    return sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, model),
        rigid_props=sim_utils.RigidBodyPropertiesCfg(disable_gravity=False, max_depenetration_velocity=5.0),
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(
            enabled_self_collisions=False, solver_position_iteration_count=8, solver_velocity_iteration_count=0
        ),
    )


def _arm(prefixes: list[str]) -> ImplicitActuatorCfg:
    """The arm group of Isaac Lab's config for the joints ``<prefix>joint[1-7]`` of each prefix."""

    def per_pair(values: tuple[float, float, float]) -> dict[str, float]:
        return {
            f"{prefix}joint[{joints}]": value
            for prefix in prefixes
            for joints, value in zip(("1-2", "3-4", "5-7"), values, strict=True)
        }

    return ImplicitActuatorCfg(
        joint_names_expr=[f"{prefix}joint[1-7]" for prefix in prefixes],
        velocity_limit_sim=per_pair((2.175, 2.175, 2.61)),
        effort_limit_sim=per_pair((40.0, 27.0, 7.0)),
        stiffness=80.0,
        damping=4.0,
    )


def _gripper(prefixes: list[str]) -> ImplicitActuatorCfg:
    return ImplicitActuatorCfg(
        joint_names_expr=[f"{prefix}finger_joint.*" for prefix in prefixes],
        velocity_limit_sim=0.2,
        effort_limit_sim=333.33,
        stiffness=2e3,
        damping=1e2,
    )


_BI = ["openarm_left_", "openarm_right_"]

OPENARM_BI_CFG = ArticulationCfg(
    spawn=_spawn("enactic_openarm_bimanual.xml"),
    init_state=ArticulationCfg.InitialStateCfg(
        joint_pos={
            "openarm_left_joint.*": 0.0,
            "openarm_right_joint.*": 0.0,
            "openarm_left_finger_joint.*": 0.0,
            "openarm_right_finger_joint.*": 0.0,
        },
    ),
    actuators={"openarm_arm": _arm(_BI), "openarm_gripper": _gripper(_BI)},
    soft_joint_pos_limit_factor=1.0,
)
"""OpenArm with two arms, as Isaac Lab configures it: both arms hanging at start."""

OPENARM_UNI_CFG = ArticulationCfg(
    spawn=_spawn("enactic_openarm.xml"),
    init_state=ArticulationCfg.InitialStateCfg(
        joint_pos={
            "openarm_joint1": 1.57,
            "openarm_joint2": 0.0,
            "openarm_joint3": -1.57,
            "openarm_joint4": 1.57,
            "openarm_joint5": 0.0,
            "openarm_joint6": 0.0,
            "openarm_joint7": 0.0,
            "openarm_finger_joint.*": 0.044,
        },
    ),
    actuators={"openarm_arm": _arm(["openarm_"]), "openarm_gripper": _gripper(["openarm_"])},
    soft_joint_pos_limit_factor=1.0,
)
"""OpenArm with one arm, as Isaac Lab configures it: the hand forward at 0.32 m, 0.34 m up, gripper open."""

OPENARM_BI_HIGH_PD_CFG = OPENARM_BI_CFG.copy()
OPENARM_BI_HIGH_PD_CFG.spawn.rigid_props.disable_gravity = True
OPENARM_BI_HIGH_PD_CFG.actuators["openarm_arm"].stiffness = 400.0
OPENARM_BI_HIGH_PD_CFG.actuators["openarm_arm"].damping = 80.0
OPENARM_BI_HIGH_PD_CFG.actuators["openarm_gripper"].stiffness = 2e3
OPENARM_BI_HIGH_PD_CFG.actuators["openarm_gripper"].damping = 1e2
"""Two arms with stiffer PD control and gravity off (Isaac Lab's, for task-space control; its bimanual reach's)."""

OPENARM_UNI_HIGH_PD_CFG = OPENARM_UNI_CFG.copy()
OPENARM_UNI_HIGH_PD_CFG.spawn.rigid_props.disable_gravity = True
OPENARM_UNI_HIGH_PD_CFG.actuators["openarm_arm"].stiffness = 400.0
OPENARM_UNI_HIGH_PD_CFG.actuators["openarm_arm"].damping = 80.0
"""One arm with stiffer PD control and gravity off (Isaac Lab's, for task-space control)."""
