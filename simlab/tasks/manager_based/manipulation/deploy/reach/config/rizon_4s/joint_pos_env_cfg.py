"""Deployed reach with the Flexiv Rizon 4s, incremental joint-position actions (Isaac Lab's
``config/rizon_4s``).

As the UR10e's: the rewards (and simlab's success criterion) read the ``flange`` through the frame
transformer ``ee_frame_wrt_base_frame``, whose source is ``base_link`` turned half a turn about z.
Commands lie within 0.4 m of a point 0.4 m in front of and above the base (0.35 m vertically), the
tool pointing down within 90 degrees and turned anywhere about the vertical.
"""

import math

from simlab.managers import SceneEntityCfg
from simlab.markers.config import FRAME_MARKER_CFG
from simlab.robots import FLEXIV_RIZON4S_CFG
from simlab.sensors.frame_transformer.frame_transformer_cfg import FrameTransformerCfg, OffsetCfg
from simlab.utils import configclass

from .... import mdp
from ....reach.reach_env_cfg import ReachEnvCfg


@configclass
class Rizon4sReachEnvCfg(ReachEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        arm = ["joint[1-2]", "joint[3-4]", "joint[5-7]"]
        self.events.robot_joint_stiffness_and_damping.params["asset_cfg"].joint_names = arm
        self.events.joint_friction.params["asset_cfg"].joint_names = arm
        self.scene.robot = FLEXIV_RIZON4S_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        for term in ("end_effector_keypoint_tracking", "end_effector_keypoint_tracking_exp"):
            getattr(self.rewards, term).params["asset_cfg"] = SceneEntityCfg("ee_frame_wrt_base_frame")
        self.scene.ee_frame_wrt_base_frame = FrameTransformerCfg(
            prim_path="{ENV_REGEX_NS}/Robot/base_link",
            visualizer_cfg=FRAME_MARKER_CFG.replace(prim_path="/Visuals/FrameTransformer"),
            source_frame_offset=OffsetCfg(pos=(0.0, 0.0, 0.0), rot=(0.0, 0.0, 0.0, 1.0)),  # half a turn about z
            target_frames=[FrameTransformerCfg.FrameCfg(prim_path="{ENV_REGEX_NS}/Robot/flange", name="end_effector")],
        )
        self.commands.ee_pose.debug_vis = True
        self.actions.arm_action = mdp.RelativeJointPositionActionCfg(
            asset_name="robot", joint_names=["joint[1-7]"], scale=0.0625, use_zero_offset=True
        )
        self.commands.ee_pose.body_name = "flange"
        self.target_pos_centre = (0.4, 0.0, 0.4)
        self.target_pos_range = (0.4, 0.4, 0.35)
        self.target_rot_centre = (math.pi, 0.0, 0.0)  # the tool pointing down
        self.target_rot_range = (math.pi / 2, math.pi / 2, math.pi)
        ranges = self.commands.ee_pose.ranges
        for i, axis in enumerate(("x", "y", "z")):
            centre, half = self.target_pos_centre[i], self.target_pos_range[i]
            setattr(ranges, f"pos_{axis}", (centre - half, centre + half))
        for i, angle in enumerate(("roll", "pitch", "yaw")):
            centre, half = self.target_rot_centre[i], self.target_rot_range[i]
            setattr(ranges, angle, (centre - half, centre + half))


@configclass
class Rizon4sReachEnvCfg_PLAY(Rizon4sReachEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.scene.num_envs = 50
        self.scene.env_spacing = 2.5
        self.observations.policy.enable_corruption = False
