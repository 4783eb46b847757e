"""In-hand object reorientation, manager-based (Isaac Lab's ``manager_based/manipulation/inhand``).

A hand (set by each robot's config, ``config/<robot>``) holds a cube (Isaac Lab's DexCube, 6 cm,
400 kg/m^3) palm up and turns it to goal orientations; each goal reached is replaced at once.
Actions: joint position targets over the joint limits, smoothed (EMA, alpha 0.95). Observations:
joint positions (normalized) and velocities, the cube's pose and velocities, the goal pose and the
rotation to it, the last actions. Rewards: ``1 / (orientation error + 0.1)``, a 250 bonus per goal,
joint-velocity, action and action-rate penalties. Episodes end after 20 s, at 50 goals, or when the
cube is 0.3 m from the hand. Start-up randomization of friction, masses and joint gains as Isaac Lab's.

MuJoCo: elliptic friction cones with impratio 10 and per-world buffers as the direct Allegro task's.
"""

from __future__ import annotations

from dataclasses import MISSING

import simlab.sim as sim_utils
from simlab.assets import ArticulationCfg, AssetBaseCfg, RigidObjectCfg
from simlab.envs import ManagerBasedRLEnvCfg
from simlab.managers import EventTermCfg as EventTerm
from simlab.managers import ObservationGroupCfg as ObsGroup
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.managers import RewardTermCfg as RewTerm
from simlab.managers import SceneEntityCfg
from simlab.managers import TerminationTermCfg as DoneTerm
from simlab.robots.dex_cube import dex_cube_cfg
from simlab.scene import InteractiveSceneCfg
from simlab.sim import MujocoCfg, PhysxCfg, SimulationCfg
from simlab.sim.spawners.materials.physics_materials_cfg import RigidBodyMaterialCfg
from simlab.utils import configclass
from simlab.utils.noise import AdditiveGaussianNoiseCfg as Gnoise

from . import mdp

##
# Scene definition
##


@configclass
class InHandObjectSceneCfg(InteractiveSceneCfg):
    """A dexterous hand and the object it holds."""

    robot: ArticulationCfg = MISSING
    object: RigidObjectCfg = RigidObjectCfg(
        prim_path="{ENV_REGEX_NS}/object",
        spawn=dex_cube_cfg(scale=1.0, density=400.0),
        init_state=RigidObjectCfg.InitialStateCfg(pos=(0.0, -0.19, 0.56), rot=(1.0, 0.0, 0.0, 0.0)),
    )
    light = AssetBaseCfg(
        prim_path="/World/light", spawn=sim_utils.DistantLightCfg(color=(0.95, 0.95, 0.95), intensity=1000.0)
    )
    dome_light = AssetBaseCfg(
        prim_path="/World/domeLight", spawn=sim_utils.DomeLightCfg(color=(0.02, 0.02, 0.02), intensity=1000.0)
    )


##
# MDP settings
##


@configclass
class CommandsCfg:
    object_pose = mdp.InHandReOrientationCommandCfg(
        asset_name="object",
        init_pos_offset=(0.0, 0.0, -0.04),
        update_goal_on_success=True,
        orientation_success_threshold=0.1,
        make_quat_unique=False,
        marker_pos_offset=(-0.2, -0.06, 0.08),
        debug_vis=True,
    )


@configclass
class ActionsCfg:
    joint_pos = mdp.EMAJointPositionToLimitsActionCfg(
        asset_name="robot", joint_names=[".*"], alpha=0.95, rescale_to_limits=True
    )


@configclass
class ObservationsCfg:
    @configclass
    class KinematicObsGroupCfg(ObsGroup):
        """The full kinematic state (no accelerations or forces)."""

        # -- robot terms
        joint_pos = ObsTerm(func=mdp.joint_pos_limit_normalized, noise=Gnoise(std=0.005))
        joint_vel = ObsTerm(func=mdp.joint_vel_rel, scale=0.2, noise=Gnoise(std=0.01))
        # -- object terms
        object_pos = ObsTerm(
            func=mdp.root_pos_w, noise=Gnoise(std=0.002), params={"asset_cfg": SceneEntityCfg("object")}
        )
        object_quat = ObsTerm(
            func=mdp.root_quat_w, params={"asset_cfg": SceneEntityCfg("object"), "make_quat_unique": False}
        )
        object_lin_vel = ObsTerm(
            func=mdp.root_lin_vel_w, noise=Gnoise(std=0.002), params={"asset_cfg": SceneEntityCfg("object")}
        )
        object_ang_vel = ObsTerm(
            func=mdp.root_ang_vel_w,
            scale=0.2,
            noise=Gnoise(std=0.002),
            params={"asset_cfg": SceneEntityCfg("object")},
        )
        # -- command terms
        goal_pose = ObsTerm(func=mdp.generated_commands, params={"command_name": "object_pose"})
        goal_quat_diff = ObsTerm(
            func=mdp.goal_quat_diff,
            params={"asset_cfg": SceneEntityCfg("object"), "command_name": "object_pose", "make_quat_unique": False},
        )
        # -- action terms
        last_action = ObsTerm(func=mdp.last_action)

        def __post_init__(self):
            self.enable_corruption = True
            self.concatenate_terms = True

    @configclass
    class NoVelocityKinematicObsGroupCfg(KinematicObsGroupCfg):
        """The kinematic state without the joints' and the object's velocities."""

        def __post_init__(self):
            super().__post_init__()
            self.joint_vel = None
            self.object_lin_vel = None
            self.object_ang_vel = None

    policy: KinematicObsGroupCfg = KinematicObsGroupCfg()


@configclass
class EventCfg:
    # startup
    # -- robot
    robot_physics_material = EventTerm(
        func=mdp.randomize_rigid_body_material,
        mode="startup",
        params={
            "asset_cfg": SceneEntityCfg("robot", body_names=".*"),
            "static_friction_range": (0.7, 1.3),
            "dynamic_friction_range": (0.7, 1.3),
            "restitution_range": (0.0, 0.0),
            "num_buckets": 250,
        },
    )
    robot_scale_mass = EventTerm(
        func=mdp.randomize_rigid_body_mass,
        mode="startup",
        params={
            "asset_cfg": SceneEntityCfg("robot", body_names=".*"),
            "mass_distribution_params": (0.95, 1.05),
            "operation": "scale",
        },
    )
    robot_joint_stiffness_and_damping = EventTerm(
        func=mdp.randomize_actuator_gains,
        mode="startup",
        params={
            "asset_cfg": SceneEntityCfg("robot", joint_names=".*"),
            "stiffness_distribution_params": (0.3, 3.0),  # default: 1.0 (Isaac Lab 2.x: 3.0)
            "damping_distribution_params": (0.75, 1.5),  # default: 0.1
            "operation": "scale",
            "distribution": "log_uniform",
        },
    )
    # -- object
    object_physics_material = EventTerm(
        func=mdp.randomize_rigid_body_material,
        mode="startup",
        params={
            "asset_cfg": SceneEntityCfg("object", body_names=".*"),
            "static_friction_range": (0.7, 1.3),
            "dynamic_friction_range": (0.7, 1.3),
            "restitution_range": (0.0, 0.0),
            "num_buckets": 250,
        },
    )
    object_scale_mass = EventTerm(
        func=mdp.randomize_rigid_body_mass,
        mode="startup",
        params={
            "asset_cfg": SceneEntityCfg("object"),
            "mass_distribution_params": (0.4, 1.6),
            "operation": "scale",
        },
    )

    # reset
    reset_object = EventTerm(
        func=mdp.reset_root_state_uniform,
        mode="reset",
        params={
            "pose_range": {"x": [-0.01, 0.01], "y": [-0.01, 0.01], "z": [-0.01, 0.01]},
            "velocity_range": {},
            "asset_cfg": SceneEntityCfg("object", body_names=".*"),
        },
    )
    reset_robot_joints = EventTerm(
        func=mdp.reset_joints_within_limits_range,
        mode="reset",
        params={
            "position_range": {".*": [0.2, 0.2]},
            "velocity_range": {".*": [0.0, 0.0]},
            "use_default_offset": True,
            "operation": "scale",
        },
    )


@configclass
class RewardsCfg:
    # -- task
    track_orientation_inv_l2 = RewTerm(
        func=mdp.track_orientation_inv_l2,
        weight=1.0,
        params={"object_cfg": SceneEntityCfg("object"), "rot_eps": 0.1, "command_name": "object_pose"},
    )
    success_bonus = RewTerm(
        func=mdp.success_bonus,
        weight=250.0,
        params={"object_cfg": SceneEntityCfg("object"), "command_name": "object_pose"},
    )
    # -- penalties
    joint_vel_l2 = RewTerm(func=mdp.joint_vel_l2, weight=-2.5e-5)
    action_l2 = RewTerm(func=mdp.action_l2, weight=-0.0001)
    action_rate_l2 = RewTerm(func=mdp.action_rate_l2, weight=-0.01)


@configclass
class TerminationsCfg:
    time_out = DoneTerm(func=mdp.time_out, time_out=True)
    max_consecutive_success = DoneTerm(
        func=mdp.max_consecutive_success, params={"num_success": 50, "command_name": "object_pose"}
    )
    object_out_of_reach = DoneTerm(func=mdp.object_away_from_robot, params={"threshold": 0.3})


##
# Environment configuration
##


@configclass
class InHandObjectEnvCfg(ManagerBasedRLEnvCfg):
    """The in-hand reorientation env; a robot config sets ``scene.robot``."""

    scene: InHandObjectSceneCfg = InHandObjectSceneCfg(num_envs=8192, env_spacing=0.6)
    sim: SimulationCfg = SimulationCfg(
        physics_material=RigidBodyMaterialCfg(static_friction=1.0, dynamic_friction=1.0),
        physx=PhysxCfg(
            bounce_threshold_velocity=0.2, gpu_max_rigid_contact_count=2**20, gpu_max_rigid_patch_count=2**23
        ),
        # per world: peaks of 17 contacts and 84 constraint rows measured under random actions (8 worlds,
        # 150 steps, the Allegro at kp 1; 19 and 92 at kp 3; tests/test_inhand_manipulation.py), with room
        # for more than twice that
        mujoco=MujocoCfg(cone="elliptic", impratio=10.0, nconmax=48, njmax=256),
    )
    observations: ObservationsCfg = ObservationsCfg()
    actions: ActionsCfg = ActionsCfg()
    commands: CommandsCfg = CommandsCfg()
    rewards: RewardsCfg = RewardsCfg()
    terminations: TerminationsCfg = TerminationsCfg()
    events: EventCfg = EventCfg()

    def __post_init__(self):
        self.decimation = 4
        self.episode_length_s = 20.0
        self.sim.dt = 1.0 / 120.0
        self.sim.render_interval = self.decimation
        # videos look at env 0's hand, the cube and the goal marker beside it (Isaac Lab: eye (2, 2, 2))
        self.viewer.eye = (0.45, 0.25, 0.9)
        self.viewer.lookat = (-0.05, -0.2, 0.55)
        self.viewer.origin_type = "env"
