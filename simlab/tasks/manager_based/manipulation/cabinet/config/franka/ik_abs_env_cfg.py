"""Open the drawer with the Franka arm, absolute differential-IK actions (Isaac Lab's ``ik_abs_env_cfg.py``).

The action is the hand's target pose in the robot's root frame (x, y, z, qw, qx, qy, qz) for a point
10.7 cm along the hand's z axis, then the gripper (open / close), as ``open_cabinet_sm.py`` sends it.
"""

from simlab.controllers import DifferentialIKControllerCfg
from simlab.robots.franka import FRANKA_PANDA_HIGH_PD_CFG
from simlab.utils import configclass

from ... import mdp
from . import joint_pos_env_cfg


@configclass
class FrankaCabinetEnvCfg(joint_pos_env_cfg.FrankaCabinetEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        # a stiffer PD controller so that the IK targets are tracked
        self.scene.robot = FRANKA_PANDA_HIGH_PD_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        self.actions.arm_action = mdp.DifferentialInverseKinematicsActionCfg(
            asset_name="robot",
            joint_names=["panda_joint.*"],
            body_name="panda_hand",
            controller=DifferentialIKControllerCfg(command_type="pose", use_relative_mode=False, ik_method="dls"),
            body_offset=mdp.DifferentialInverseKinematicsActionCfg.OffsetCfg(pos=(0.0, 0.0, 0.107)),
        )


@configclass
class FrankaCabinetEnvCfg_PLAY(FrankaCabinetEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.scene.num_envs = 50
        self.scene.env_spacing = 2.5
        self.observations.policy.enable_corruption = False
