"""Stack cubes with the Franka arm, absolute end-effector poses by differential IK (Isaac Lab's
``stack_ik_abs_env_cfg.py``): an action is the hand's pose (x, y, z, qw, qx, qy, qz) in the robot's
root frame and the gripper command."""

from simlab.controllers import DifferentialIKControllerCfg
from simlab.envs.mdp.actions.actions_cfg import DifferentialInverseKinematicsActionCfg
from simlab.robots.franka import FRANKA_PANDA_HIGH_PD_CFG
from simlab.utils import configclass

from . import stack_joint_pos_env_cfg


@configclass
class FrankaCubeStackEnvCfg(stack_joint_pos_env_cfg.FrankaCubeStackEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        # the stiffer PD (and no gravity on the arm) tracks the IK targets closely
        self.scene.robot = FRANKA_PANDA_HIGH_PD_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        self.actions.arm_action = DifferentialInverseKinematicsActionCfg(
            asset_name="robot",
            joint_names=["panda_joint.*"],
            body_name="panda_hand",
            controller=DifferentialIKControllerCfg(command_type="pose", use_relative_mode=False, ik_method="dls"),
        )
