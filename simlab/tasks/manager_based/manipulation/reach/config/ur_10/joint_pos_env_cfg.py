"""Reach with the UR10 arm, joint-position actions (Isaac Lab's ``config/ur_10/joint_pos_env_cfg.py``)."""

import math

from simlab.robots.universal_robots import UR10_CFG
from simlab.utils import configclass

from ... import mdp
from ...reach_env_cfg import ReachEnvCfg


@configclass
class UR10ReachEnvCfg(ReachEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.scene.robot = UR10_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        self.events.reset_robot_joints.params["position_range"] = (0.75, 1.25)
        for term in ("end_effector_position_tracking", "end_effector_position_tracking_fine_grained"):
            getattr(self.rewards, term).params["asset_cfg"].body_names = ["ee_link"]
        self.rewards.end_effector_orientation_tracking.params["asset_cfg"].body_names = ["ee_link"]
        self.actions.arm_action = mdp.JointPositionActionCfg(
            asset_name="robot", joint_names=[".*"], scale=0.5, use_default_offset=True
        )
        # the tool axis is ee_link's x axis: a pitch of pi/2 points it down
        self.commands.ee_pose.body_name = "ee_link"
        self.commands.ee_pose.ranges.pitch = (math.pi / 2, math.pi / 2)


@configclass
class UR10ReachEnvCfg_PLAY(UR10ReachEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.scene.num_envs = 50
        self.scene.env_spacing = 2.5
        self.observations.policy.enable_corruption = False
