"""Deployed reach with the UR10e, incremental joint-position actions (Isaac Lab's ``config/ur_10e``).

Universal Robots' controller gives poses in its "base" frame, ``base_link`` turned half a turn about z;
the policy learns to track commands in that frame: the rewards (and simlab's success criterion) read
``wrist_3_link`` through the frame transformer ``ee_frame_wrt_base_frame``, whose source is that turn
of ``base_link``. Commands lie 0.64-1.14 m in front of the base, the tool pointing down within 30
degrees and turned within 120 degrees about the vertical. Each action moves the joint targets by at
most 0.0625 rad from where they are.
"""

import math

from simlab.managers import SceneEntityCfg
from simlab.markers.config import FRAME_MARKER_CFG
from simlab.robots import UR10e_CFG
from simlab.sensors.frame_transformer.frame_transformer_cfg import FrameTransformerCfg, OffsetCfg
from simlab.utils import configclass

from .... import mdp
from ....reach.reach_env_cfg import ReachEnvCfg


@configclass
class UR10eReachEnvCfg(ReachEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        arm = ["shoulder_.*", "elbow_.*", "wrist_.*"]
        self.events.robot_joint_stiffness_and_damping.params["asset_cfg"].joint_names = arm
        self.events.joint_friction.params["asset_cfg"].joint_names = arm
        self.scene.robot = UR10e_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        for term in ("end_effector_keypoint_tracking", "end_effector_keypoint_tracking_exp"):
            getattr(self.rewards, term).params["asset_cfg"] = SceneEntityCfg("ee_frame_wrt_base_frame")
        self.scene.ee_frame_wrt_base_frame = FrameTransformerCfg(
            prim_path="{ENV_REGEX_NS}/Robot/base_link",
            visualizer_cfg=FRAME_MARKER_CFG.replace(prim_path="/Visuals/FrameTransformer"),
            source_frame_offset=OffsetCfg(pos=(0.0, 0.0, 0.0), rot=(0.0, 0.0, 0.0, 1.0)),  # half a turn about z
            target_frames=[
                FrameTransformerCfg.FrameCfg(prim_path="{ENV_REGEX_NS}/Robot/wrist_3_link", name="end_effector")
            ],
        )
        # the command is drawn as if in base_link's frame, which is not the frame it is tracked in
        self.commands.ee_pose.debug_vis = False
        self.actions.arm_action = mdp.RelativeJointPositionActionCfg(
            asset_name="robot", joint_names=[".*"], scale=0.0625, use_zero_offset=True
        )
        self.commands.ee_pose.body_name = "wrist_3_link"
        self.target_pos_centre = (0.8875, -0.225, 0.2)
        self.target_pos_range = (0.25, 0.125, 0.1)
        self.target_rot_centre = (math.pi, 0.0, -math.pi / 2)  # the tool pointing down
        self.target_rot_range = (math.pi / 6, math.pi / 6, math.pi * 2 / 3)
        ranges = self.commands.ee_pose.ranges
        for i, axis in enumerate(("x", "y", "z")):
            centre, half = self.target_pos_centre[i], self.target_pos_range[i]
            setattr(ranges, f"pos_{axis}", (centre - half, centre + half))
        for i, angle in enumerate(("roll", "pitch", "yaw")):
            centre, half = self.target_rot_centre[i], self.target_rot_range[i]
            setattr(ranges, angle, (centre - half, centre + half))


@configclass
class UR10eReachEnvCfg_PLAY(UR10eReachEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.scene.num_envs = 50
        self.scene.env_spacing = 2.5
        self.observations.policy.enable_corruption = False
