"""Reach with both arms of the two-arm OpenArm (Isaac Lab's ``config/openarm/bimanual/reach_openarm_bi_env_cfg.py``).

Each hand tracks its own pose command (``left_ee_pose``, ``right_ee_pose``) in the robot's root frame:
0.15-0.3 m ahead, 0.15-0.25 m to its side, 0.3-0.5 m up, pointing forward (pitch 3 pi/2, yaw
8 pi/9-10 pi/9, roll +-30 degrees), each resampled every 4 s. Observations: each arm's joint positions
and speeds, both commands, both arms' last actions. Rewards: per hand, position, fine-grained position
(the right hand's weighted higher, as Isaac Lab's) and orientation tracking; the action-rate and
per-arm joint-speed penalties a curriculum raises after 4500 steps. 24 s episodes; the ground at the
body's foot; no table.
"""

import math
from dataclasses import MISSING

import simlab.sim as sim_utils
from simlab.assets import ArticulationCfg, AssetBaseCfg
from simlab.envs import ManagerBasedRLEnvCfg
from simlab.managers import ActionTermCfg as ActionTerm
from simlab.managers import CurriculumTermCfg as CurrTerm
from simlab.managers import EventTermCfg as EventTerm
from simlab.managers import ObservationGroupCfg as ObsGroup
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.managers import RewardTermCfg as RewTerm
from simlab.managers import SceneEntityCfg
from simlab.managers import TerminationTermCfg as DoneTerm
from simlab.scene import InteractiveSceneCfg
from simlab.utils import configclass
from simlab.utils.noise import AdditiveUniformNoiseCfg as Unoise

from .... import mdp

LEFT_JOINTS = ["openarm_left_joint.*"]
RIGHT_JOINTS = ["openarm_right_joint.*"]


def _pose_command(pos_y: tuple[float, float]) -> mdp.UniformPoseCommandCfg:
    return mdp.UniformPoseCommandCfg(
        asset_name="robot",
        body_name=MISSING,
        resampling_time_range=(4.0, 4.0),
        debug_vis=True,
        ranges=mdp.UniformPoseCommandCfg.Ranges(
            pos_x=(0.15, 0.3),
            pos_y=pos_y,
            pos_z=(0.3, 0.5),
            roll=(-math.pi / 6, math.pi / 6),
            pitch=(3 * math.pi / 2, 3 * math.pi / 2),
            yaw=(8 * math.pi / 9, 10 * math.pi / 9),
        ),
    )


def _joint_state(func, joints: list[str]) -> ObsTerm:
    return ObsTerm(
        func=func,
        params={"asset_cfg": SceneEntityCfg("robot", joint_names=joints)},
        noise=Unoise(n_min=-0.01, n_max=0.01),
    )


def _hand_term(func, weight: float, command: str, **params) -> RewTerm:
    return RewTerm(
        func=func,
        weight=weight,
        params={"asset_cfg": SceneEntityCfg("robot", body_names=MISSING), "command_name": command, **params},
    )


@configclass
class ReachSceneCfg(InteractiveSceneCfg):
    ground = AssetBaseCfg(
        prim_path="/World/ground",
        spawn=sim_utils.GroundPlaneCfg(),
        init_state=AssetBaseCfg.InitialStateCfg(pos=(0.0, 0.0, 0.0)),
    )
    robot: ArticulationCfg = MISSING
    light = AssetBaseCfg(
        prim_path="/World/light", spawn=sim_utils.DomeLightCfg(color=(0.75, 0.75, 0.75), intensity=2500.0)
    )


@configclass
class CommandsCfg:
    left_ee_pose = _pose_command((0.15, 0.25))
    right_ee_pose = _pose_command((-0.25, -0.15))


@configclass
class ActionsCfg:
    left_arm_action: ActionTerm = MISSING
    right_arm_action: ActionTerm = MISSING


@configclass
class ObservationsCfg:
    @configclass
    class PolicyCfg(ObsGroup):
        left_joint_pos = _joint_state(mdp.joint_pos_rel, LEFT_JOINTS)
        right_joint_pos = _joint_state(mdp.joint_pos_rel, RIGHT_JOINTS)
        left_joint_vel = _joint_state(mdp.joint_vel_rel, LEFT_JOINTS)
        right_joint_vel = _joint_state(mdp.joint_vel_rel, RIGHT_JOINTS)
        left_pose_command = ObsTerm(func=mdp.generated_commands, params={"command_name": "left_ee_pose"})
        right_pose_command = ObsTerm(func=mdp.generated_commands, params={"command_name": "right_ee_pose"})
        left_actions = ObsTerm(func=mdp.last_action, params={"action_name": "left_arm_action"})
        right_actions = ObsTerm(func=mdp.last_action, params={"action_name": "right_arm_action"})

        def __post_init__(self):
            self.enable_corruption = True
            self.concatenate_terms = True

    policy: PolicyCfg = PolicyCfg()


@configclass
class EventCfg:
    reset_robot_joints = EventTerm(
        func=mdp.reset_joints_by_scale,
        mode="reset",
        params={"position_range": (0.5, 1.5), "velocity_range": (0.0, 0.0)},
    )


@configclass
class RewardsCfg:
    left_end_effector_position_tracking = _hand_term(mdp.position_command_error, -0.2, "left_ee_pose")
    right_end_effector_position_tracking = _hand_term(mdp.position_command_error, -0.25, "right_ee_pose")
    left_end_effector_position_tracking_fine_grained = _hand_term(
        mdp.position_command_error_tanh, 0.1, "left_ee_pose", std=0.1
    )
    right_end_effector_position_tracking_fine_grained = _hand_term(
        mdp.position_command_error_tanh, 0.2, "right_ee_pose", std=0.1
    )
    left_end_effector_orientation_tracking = _hand_term(mdp.orientation_command_error, -0.1, "left_ee_pose")
    right_end_effector_orientation_tracking = _hand_term(mdp.orientation_command_error, -0.1, "right_ee_pose")
    action_rate = RewTerm(func=mdp.action_rate_l2, weight=-0.0001)
    left_joint_vel = RewTerm(
        func=mdp.joint_vel_l2, weight=-0.0001, params={"asset_cfg": SceneEntityCfg("robot", joint_names=LEFT_JOINTS)}
    )
    right_joint_vel = RewTerm(
        func=mdp.joint_vel_l2, weight=-0.0001, params={"asset_cfg": SceneEntityCfg("robot", joint_names=RIGHT_JOINTS)}
    )


@configclass
class TerminationsCfg:
    time_out = DoneTerm(func=mdp.time_out, time_out=True)


@configclass
class CurriculumCfg:
    action_rate = CurrTerm(
        func=mdp.modify_reward_weight, params={"term_name": "action_rate", "weight": -0.005, "num_steps": 4500}
    )
    left_joint_vel = CurrTerm(
        func=mdp.modify_reward_weight, params={"term_name": "left_joint_vel", "weight": -0.001, "num_steps": 4500}
    )
    right_joint_vel = CurrTerm(
        func=mdp.modify_reward_weight, params={"term_name": "right_joint_vel", "weight": -0.001, "num_steps": 4500}
    )


@configclass
class ReachEnvCfg(ManagerBasedRLEnvCfg):
    scene: ReachSceneCfg = ReachSceneCfg(num_envs=4096, env_spacing=2.5)
    observations: ObservationsCfg = ObservationsCfg()
    actions: ActionsCfg = ActionsCfg()
    commands: CommandsCfg = CommandsCfg()
    rewards: RewardsCfg = RewardsCfg()
    terminations: TerminationsCfg = TerminationsCfg()
    events: EventCfg = EventCfg()
    curriculum: CurriculumCfg = CurriculumCfg()

    def __post_init__(self):
        self.decimation = 2
        self.sim.render_interval = self.decimation
        self.episode_length_s = 24.0
        self.viewer.eye = (3.5, 3.5, 3.5)
        self.sim.dt = 1.0 / 60.0
        # nothing touches in reach (the arms do not collide with each other or the body here)
        self.sim.mujoco.disable_contacts = True
