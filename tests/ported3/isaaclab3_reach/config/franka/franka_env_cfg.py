# Isaac Lab 3.0's isaaclab_tasks/core/reach/config/franka/franka_env_cfg.py (develop), written out under the
# 3.0 import mapping (isaaclab.envs.mdp -> simlab.v3.envs.mdp, isaaclab.actuators / .controllers ->
# simlab.*, isaaclab_assets -> simlab.v3.robots). What differs besides the imports:
# * the ``newton_ik`` arm preset (Newton's IK solver, isaaclab_newton.ik) and ``validate_config``, which
#   only checks that preset's physics, are left out: simlab has no Newton IK (``diffik`` is the IK here);
# * the line pointing the robot at Isaac's ``franka_panda.usda`` is left out: simlab's Franka is its MJCF.
#   The actuator gains 3.0 sets for that file are kept.

import math

import simlab.v3.envs.mdp as mdp
from simlab.actuators import ImplicitActuatorCfg
from simlab.controllers import DifferentialIKControllerCfg
from simlab.tasks.utils import PresetCfg
from simlab.utils.configclass import configclass
from simlab.v3.envs.mdp import DifferentialInverseKinematicsActionCfg
from simlab.v3.robots import FRANKA_PANDA_CFG

from ...reach_env_cfg import ReachEnvCfg

_FRANKA_PANDA_REACH_CFG = FRANKA_PANDA_CFG.copy()
_FRANKA_PANDA_REACH_CFG.actuators = {
    "panda_arm": ImplicitActuatorCfg(
        joint_names_expr=["panda_joint[1-7]"],
        velocity_limit_sim={"panda_joint[1-4]": 20.0, "panda_joint[5-7]": 25.0},
        stiffness={"panda_joint[1-2]": 1000.0, "panda_joint[3-4]": 750.0, "panda_joint[5-7]": 300.0},
        damping={"panda_joint[1-2]": 20.0, "panda_joint[3-4]": 4.0, "panda_joint[5-7]": 2.0},
    ),
    "panda_hand": ImplicitActuatorCfg(joint_names_expr=["panda_finger_joint.*"], stiffness=None, damping=None),
}

_IK_ACTION_SCALE = (0.05, 0.05, 0.05, 0.5, 0.5, 0.5)


@configclass
class FrankaArmActionCfg(PresetCfg):
    joint_pos: mdp.JointPositionActionCfg = mdp.JointPositionActionCfg(
        asset_name="robot", joint_names=["panda_joint.*"], scale=0.5, use_default_offset=True
    )
    diffik: DifferentialInverseKinematicsActionCfg = DifferentialInverseKinematicsActionCfg(
        asset_name="robot",
        joint_names=["panda_joint.*"],
        body_name="panda_hand",
        controller=DifferentialIKControllerCfg(
            command_type="pose", use_relative_mode=True, ik_method="dls", ik_params={"lambda_val": 0.01}
        ),
        scale=_IK_ACTION_SCALE,
        body_offset=DifferentialInverseKinematicsActionCfg.OffsetCfg(pos=[0.0, 0.0, 0.107]),
    )
    default: mdp.JointPositionActionCfg = joint_pos


@configclass
class FrankaReachEnvCfg(ReachEnvCfg):
    def __post_init__(self) -> None:
        super().__post_init__()
        self.scene.robot = _FRANKA_PANDA_REACH_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        self.rewards.end_effector_position_tracking.params["asset_cfg"].body_names = ["panda_hand"]
        self.rewards.end_effector_orientation_tracking.params["asset_cfg"].body_names = ["panda_hand"]
        self.rewards.joint_vel.params["asset_cfg"].joint_names = ["panda_joint.*"]
        self.actions.arm_action = FrankaArmActionCfg()
        # the hand's z axis points along the gripper: pitch it down
        self.commands.ee_pose.body_name = "panda_hand"
        self.commands.ee_pose.ranges.pitch = (math.pi, math.pi)
