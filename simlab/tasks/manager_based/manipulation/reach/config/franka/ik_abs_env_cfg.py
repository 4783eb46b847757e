"""Reach with the Franka arm, absolute differential-IK actions (Isaac Lab's ``ik_abs_env_cfg.py``)."""

from simlab.controllers import DifferentialIKControllerCfg
from simlab.robots.franka import FRANKA_PANDA_HIGH_PD_CFG
from simlab.utils import configclass

from ... import mdp
from . import joint_pos_env_cfg


@configclass
class FrankaReachEnvCfg(joint_pos_env_cfg.FrankaReachEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        # stiffer PD and no gravity on the robot: the IK's joint targets are tracked closely
        self.scene.robot = FRANKA_PANDA_HIGH_PD_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        self.actions.arm_action = mdp.DifferentialInverseKinematicsActionCfg(
            asset_name="robot",
            joint_names=["panda_joint.*"],
            body_name="panda_hand",
            # Isaac Lab's current absolute-IK settings: a damping of 0.45 keeps the joint steps small
            # near singular or unreachable targets, and actions in [-1, 1] span the commanded
            # workspace (centre 0.5, 0, 0.325 m; half-spans 0.15, 0.2, 0.175 m)
            controller=DifferentialIKControllerCfg(
                command_type="pose", use_relative_mode=False, ik_method="dls", ik_params={"lambda_val": 0.45}
            ),
            scale=(0.15, 0.2, 0.175, 1.0, 1.0, 1.0, 1.0),
            offset=(0.5, 0.0, 0.325, 0.0, 0.0, 0.0, 0.0),
            body_offset=mdp.DifferentialInverseKinematicsActionCfg.OffsetCfg(pos=(0.0, 0.0, 0.107)),
        )


@configclass
class FrankaReachEnvCfg_PLAY(FrankaReachEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.scene.num_envs = 50
        self.scene.env_spacing = 2.5
        self.observations.policy.enable_corruption = False
