"""Unitree G1 (29-DoF) motion tracking on flat ground (mjlab's ``Mjlab-Tracking-Flat-Unitree-G1``).

One policy per clip, as mjlab and Isaac Lab train it. ``simlab/Tracking-Flat-G1-v0`` tracks the walk
(``motions/g1_walk.npz``, made by ``scripts/tools/make_g1_clips.py``); each other shipped clip has its own
task id, so that each has its own shipped policy: ``simlab/Tracking-Flat-G1-{Turn,Wave,Twist}-v0``. Train
on any other clip with ``env.commands.motion.motion_file=<path>``. The criterion judges the clip the run
trained on.
"""

import os

from simlab.robots.unitree import G1_29DOF_ACTION_SCALE, G1_29DOF_CFG
from simlab.tasks.manager_based.tracking.tracking_env_cfg import TrackingEnvCfg
from simlab.utils import configclass

MOTIONS_DIR = os.path.join(os.path.dirname(__file__), "motions")

TRACKED_BODIES = [
    "pelvis",
    "left_hip_roll_link",
    "left_knee_link",
    "left_ankle_roll_link",
    "right_hip_roll_link",
    "right_knee_link",
    "right_ankle_roll_link",
    "torso_link",
    "left_shoulder_roll_link",
    "left_elbow_link",
    "left_wrist_yaw_link",
    "right_shoulder_roll_link",
    "right_elbow_link",
    "right_wrist_yaw_link",
]
END_EFFECTORS = ["left_ankle_roll_link", "right_ankle_roll_link", "left_wrist_yaw_link", "right_wrist_yaw_link"]


@configclass
class G1FlatTrackingEnvCfg(TrackingEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.scene.robot = G1_29DOF_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        self.actions.joint_pos.scale = G1_29DOF_ACTION_SCALE
        motion = self.commands.motion
        motion.motion_file = os.path.join(MOTIONS_DIR, "g1_walk.npz")
        motion.anchor_body_name = "torso_link"
        motion.body_names = TRACKED_BODIES
        self.terminations.ee_body_pos.params["body_names"] = END_EFFECTORS


@configclass
class G1FlatTrackingEnvCfg_PLAY(G1FlatTrackingEnvCfg):  # noqa: N801 - Isaac Lab's naming
    def __post_init__(self):
        super().__post_init__()
        self.scene.num_envs = 50
        self.observations.policy.enable_corruption = False
        self.events.push_robot = None
        # play the clip from its start, without the start-state noise
        self.commands.motion.adaptive_sampling = False
        self.commands.motion.pose_range = {}
        self.commands.motion.velocity_range = {}
        self.commands.motion.joint_position_range = (0.0, 0.0)


# The other shipped clips, one task id each (simlab/Tracking-Flat-G1-{Turn,Wave,Twist}-v0), so that each
# clip has its own shipped policy.


def _clip(name: str) -> str:
    return os.path.join(MOTIONS_DIR, f"{name}.npz")


@configclass
class G1FlatTrackingTurnEnvCfg(G1FlatTrackingEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.commands.motion.motion_file = _clip("g1_turn")


@configclass
class G1FlatTrackingTurnEnvCfg_PLAY(G1FlatTrackingEnvCfg_PLAY):  # noqa: N801
    def __post_init__(self):
        super().__post_init__()
        self.commands.motion.motion_file = _clip("g1_turn")


@configclass
class G1FlatTrackingWaveEnvCfg(G1FlatTrackingEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.commands.motion.motion_file = _clip("g1_wave")


@configclass
class G1FlatTrackingWaveEnvCfg_PLAY(G1FlatTrackingEnvCfg_PLAY):  # noqa: N801
    def __post_init__(self):
        super().__post_init__()
        self.commands.motion.motion_file = _clip("g1_wave")


@configclass
class G1FlatTrackingTwistEnvCfg(G1FlatTrackingEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.commands.motion.motion_file = _clip("g1_twist")


@configclass
class G1FlatTrackingTwistEnvCfg_PLAY(G1FlatTrackingEnvCfg_PLAY):  # noqa: N801
    def __post_init__(self):
        super().__post_init__()
        self.commands.motion.motion_file = _clip("g1_twist")
