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
    """Isaac Lab's reach rewards plus a narrow orientation term that pays for the last tenth of a
    radian: with Isaac Lab's linear orientation error alone the policies stop about 0.18 rad short
    (CPU, 1024 envs, 400 iterations: 0.187 rad mean, 6.46 cm; with this term 0.092 rad, 4.62 cm)."""

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
