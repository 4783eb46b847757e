"""Reach with one OpenArm, joint-position actions (Isaac Lab's ``config/openarm/unimanual/joint_pos_env_cfg.py``)."""

from simlab.assets import ArticulationCfg
from simlab.robots.openarm import OPENARM_UNI_CFG
from simlab.utils import configclass

from .... import mdp
from .reach_openarm_uni_env_cfg import ReachEnvCfg


@configclass
class OpenArmReachEnvCfg(ReachEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.scene.robot = OPENARM_UNI_CFG.replace(
            prim_path="{ENV_REGEX_NS}/Robot",
            init_state=ArticulationCfg.InitialStateCfg(
                joint_pos={
                    "openarm_joint1": 1.57,
                    "openarm_joint2": 0.0,
                    "openarm_joint3": -1.57,
                    "openarm_joint4": 1.57,
                    "openarm_joint5": 0.0,
                    "openarm_joint6": 0.0,
                    "openarm_joint7": 0.0,
                    "openarm_finger_joint.*": 0.0,  # the gripper closed
                },
            ),
        )
        for term in (
            "end_effector_position_tracking",
            "end_effector_position_tracking_fine_grained",
            "end_effector_orientation_tracking",
        ):
            getattr(self.rewards, term).params["asset_cfg"].body_names = ["openarm_hand"]
        self.actions.arm_action = mdp.JointPositionActionCfg(
            asset_name="robot", joint_names=["openarm_joint.*"], scale=0.5, use_default_offset=True
        )
        # the hand's z axis runs along the fingers
        self.commands.ee_pose.body_name = "openarm_hand"


@configclass
class OpenArmReachEnvCfg_PLAY(OpenArmReachEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.scene.num_envs = 50
        self.scene.env_spacing = 2.5
        self.observations.policy.enable_corruption = False
