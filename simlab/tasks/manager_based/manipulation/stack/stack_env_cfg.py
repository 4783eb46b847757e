"""Stack three cubes (Isaac Lab's ``stack_env_cfg.py``).

1/100 s physics, decimation 5, 30 s episodes. No rewards, commands or curriculum: Isaac Lab trains
this task from demonstrations (imitation learning), not with RL. Observation groups: ``policy`` (the
last action, joint state, the cubes, the end effector and the gripper, each term kept apart) and
``subtask_terms``, the signals demonstration tools read to split an episode into subtasks: ``grasp_1``
(cube 2 in the gripper), ``stack_1`` (cube 2 released on cube 1) and ``grasp_2`` (cube 3 in the
gripper). An episode ends when the cubes are stacked (``success``), when a cube falls off the table,
or at the time limit. The robot, cubes, end-effector frame and events come from ``config/``.

simlab's scene: Isaac Lab's table is a USD prop; here it is a static box whose top is at z = 0, as in
simlab's lift task. Isaac Lab's empty ``rgb_camera`` group is left out (it holds no terms).
"""

from dataclasses import MISSING

import simlab.sim as sim_utils
from simlab.assets import ArticulationCfg, AssetBaseCfg, RigidObjectCfg
from simlab.envs import ManagerBasedRLEnvCfg
from simlab.managers import ObservationGroupCfg as ObsGroup
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.managers import SceneEntityCfg
from simlab.managers import TerminationTermCfg as DoneTerm
from simlab.scene import InteractiveSceneCfg
from simlab.sensors import FrameTransformerCfg
from simlab.utils import configclass

from . import mdp


@configclass
class ObjectTableSceneCfg(InteractiveSceneCfg):
    """Robot, end-effector frame and three cubes (set by the robot's config), a table, ground, light."""

    robot: ArticulationCfg = MISSING
    ee_frame: FrameTransformerCfg = MISSING
    cube_1: RigidObjectCfg = MISSING
    cube_2: RigidObjectCfg = MISSING
    cube_3: RigidObjectCfg = MISSING
    table = AssetBaseCfg(
        prim_path="{ENV_REGEX_NS}/Table",
        init_state=AssetBaseCfg.InitialStateCfg(pos=(0.35, 0.0, -0.5)),
        spawn=sim_utils.CuboidCfg(
            size=(1.2, 1.2, 1.0), visual_material=sim_utils.PreviewSurfaceCfg(diffuse_color=(0.55, 0.45, 0.35))
        ),
    )
    plane = AssetBaseCfg(
        prim_path="/World/GroundPlane",
        init_state=AssetBaseCfg.InitialStateCfg(pos=(0.0, 0.0, -1.05)),
        spawn=sim_utils.GroundPlaneCfg(),
    )
    light = AssetBaseCfg(
        prim_path="/World/light", spawn=sim_utils.DomeLightCfg(color=(0.75, 0.75, 0.75), intensity=3000.0)
    )


@configclass
class ActionsCfg:
    arm_action: mdp.JointPositionActionCfg | mdp.DifferentialInverseKinematicsActionCfg = MISSING
    gripper_action: mdp.BinaryJointPositionActionCfg = MISSING


@configclass
class ObservationsCfg:
    @configclass
    class PolicyCfg(ObsGroup):
        actions = ObsTerm(func=mdp.last_action)
        joint_pos = ObsTerm(func=mdp.joint_pos_rel)
        joint_vel = ObsTerm(func=mdp.joint_vel_rel)
        object = ObsTerm(func=mdp.object_obs)
        cube_positions = ObsTerm(func=mdp.cube_positions_in_world_frame)
        cube_orientations = ObsTerm(func=mdp.cube_orientations_in_world_frame)
        eef_pos = ObsTerm(func=mdp.ee_frame_pos)
        eef_quat = ObsTerm(func=mdp.ee_frame_quat)
        gripper_pos = ObsTerm(func=mdp.gripper_pos)

        def __post_init__(self):
            self.enable_corruption = False
            self.concatenate_terms = False

    @configclass
    class SubtaskCfg(ObsGroup):
        grasp_1 = ObsTerm(
            func=mdp.object_grasped,
            params={
                "robot_cfg": SceneEntityCfg("robot"),
                "ee_frame_cfg": SceneEntityCfg("ee_frame"),
                "object_cfg": SceneEntityCfg("cube_2"),
            },
        )
        stack_1 = ObsTerm(
            func=mdp.object_stacked,
            params={
                "robot_cfg": SceneEntityCfg("robot"),
                "upper_object_cfg": SceneEntityCfg("cube_2"),
                "lower_object_cfg": SceneEntityCfg("cube_1"),
            },
        )
        grasp_2 = ObsTerm(
            func=mdp.object_grasped,
            params={
                "robot_cfg": SceneEntityCfg("robot"),
                "ee_frame_cfg": SceneEntityCfg("ee_frame"),
                "object_cfg": SceneEntityCfg("cube_3"),
            },
        )

        def __post_init__(self):
            self.enable_corruption = False
            self.concatenate_terms = False

    policy: PolicyCfg = PolicyCfg()
    subtask_terms: SubtaskCfg = SubtaskCfg()


@configclass
class TerminationsCfg:
    time_out = DoneTerm(func=mdp.time_out, time_out=True)
    cube_1_dropping = DoneTerm(
        func=mdp.root_height_below_minimum, params={"minimum_height": -0.05, "asset_cfg": SceneEntityCfg("cube_1")}
    )
    cube_2_dropping = DoneTerm(
        func=mdp.root_height_below_minimum, params={"minimum_height": -0.05, "asset_cfg": SceneEntityCfg("cube_2")}
    )
    cube_3_dropping = DoneTerm(
        func=mdp.root_height_below_minimum, params={"minimum_height": -0.05, "asset_cfg": SceneEntityCfg("cube_3")}
    )
    success = DoneTerm(func=mdp.cubes_stacked)


@configclass
class StackEnvCfg(ManagerBasedRLEnvCfg):
    scene: ObjectTableSceneCfg = ObjectTableSceneCfg(num_envs=4096, env_spacing=2.5, replicate_physics=False)
    observations: ObservationsCfg = ObservationsCfg()
    actions: ActionsCfg = ActionsCfg()
    terminations: TerminationsCfg = TerminationsCfg()
    commands = None
    rewards = None
    events = None
    curriculum = None

    # the gripper, for the subtask signals and the success check: the two finger joints (None: the
    # gripper action's), their open position [m] and how far from it a finger counts as closed [m];
    # the defaults are the Franka's
    gripper_joint_names: list[str] | None = None
    gripper_open_val: float = 0.04
    gripper_threshold: float = 0.005

    def __post_init__(self):
        self.decimation = 5
        self.episode_length_s = 30.0
        self.sim.dt = 0.01
        self.sim.render_interval = 2
