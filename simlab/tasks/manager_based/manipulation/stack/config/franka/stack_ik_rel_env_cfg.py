"""Stack cubes with the Franka arm, relative end-effector poses by differential IK (Isaac Lab's
``stack_ik_rel_env_cfg.py``): an action is a change of the fingertip frame's pose (dx, dy, dz, droll,
dpitch, dyaw, scaled by 0.5) and the gripper command."""

from simlab.controllers import DifferentialIKControllerCfg
from simlab.envs.mdp.actions.actions_cfg import DifferentialInverseKinematicsActionCfg
from simlab.robots.franka import FRANKA_PANDA_HIGH_PD_CFG
from simlab.utils import configclass

from . import stack_joint_pos_env_cfg


@configclass
class FrankaCubeStackEnvCfg(stack_joint_pos_env_cfg.FrankaCubeStackEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.scene.robot = FRANKA_PANDA_HIGH_PD_CFG.replace(
            prim_path="{ENV_REGEX_NS}/Robot", init_state=self.scene.robot.init_state
        )
        self.actions.arm_action = DifferentialInverseKinematicsActionCfg(
            asset_name="robot",
            joint_names=["panda_joint.*"],
            body_name="panda_hand",
            controller=DifferentialIKControllerCfg(command_type="pose", use_relative_mode=True, ik_method="dls"),
            scale=0.5,
            body_offset=DifferentialInverseKinematicsActionCfg.OffsetCfg(pos=[0.0, 0.0, 0.107]),
        )
