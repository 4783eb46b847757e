"""Reach with the Franka arm, joint-position actions (Isaac Lab's ``config/franka/joint_pos_env_cfg.py``)."""

import math

from simlab.managers import RewardTermCfg as RewTerm
from simlab.managers import SceneEntityCfg
from simlab.robots.franka import FRANKA_PANDA_CFG
from simlab.utils import configclass

from ... import mdp
from ...reach_env_cfg import ReachEnvCfg, RewardsCfg


@configclass
class FrankaReachRewardsCfg(RewardsCfg):
    """Isaac Lab's reach rewards plus two narrower ones that pay for the last centimetres and the last
    tenth of a radian: Isaac Lab's terms (a linear error and a tanh over 10 cm) barely tell 3 cm from
    1 cm, and the policies they train stop a few centimetres and about 0.2 rad short of the target.
    The weights balance the two: near the target 1 cm of position is worth about 0.1 rad of
    orientation (with a position term over 2 cm instead, too narrow to pull from 5 cm, a CPU run
    bought 0.18 -> 0.11 rad of orientation with 4.8 -> 7.8 cm of position)."""

    end_effector_position_tracking_precise = RewTerm(
        func=mdp.position_command_error_tanh,
        weight=0.3,
        params={
            "asset_cfg": SceneEntityCfg("robot", body_names=["panda_hand"]),
            "std": 0.05,
            "command_name": "ee_pose",
        },
    )
    end_effector_orientation_tracking_fine_grained = RewTerm(
        func=mdp.orientation_command_error_tanh,
        weight=0.1,
        params={"asset_cfg": SceneEntityCfg("robot", body_names=["panda_hand"]), "std": 0.1, "command_name": "ee_pose"},
    )


@configclass
class FrankaReachEnvCfg(ReachEnvCfg):
    rewards: FrankaReachRewardsCfg = FrankaReachRewardsCfg()

    def __post_init__(self):
        super().__post_init__()
        self.scene.robot = FRANKA_PANDA_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        self.rewards.end_effector_position_tracking.params["asset_cfg"].body_names = ["panda_hand"]
        self.rewards.end_effector_position_tracking_fine_grained.params["asset_cfg"].body_names = ["panda_hand"]
        self.rewards.end_effector_orientation_tracking.params["asset_cfg"].body_names = ["panda_hand"]
        self.actions.arm_action = mdp.JointPositionActionCfg(
            asset_name="robot", joint_names=["panda_joint.*"], scale=0.5, use_default_offset=True
        )
        # the hand's z axis points along the end effector: commands point it down
        self.commands.ee_pose.body_name = "panda_hand"
        self.commands.ee_pose.ranges.pitch = (math.pi, math.pi)


@configclass
class FrankaReachEnvCfg_PLAY(FrankaReachEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.scene.num_envs = 50
        self.scene.env_spacing = 2.5
        self.observations.policy.enable_corruption = False
