"""Shadow Hand cube reorientation, direct workflow (Isaac Lab's ``direct/shadow_hand``).

Isaac Lab's settings: 1/120 s physics, 2 physics steps per action, 10 s episodes, 20 actions (the
coupled distal joints follow), 157 observations ("full"), a 6 cm DexCube (567 kg/m^3) dropped on the
palm-up hand, a goal reached within 0.1 rad, a 250 bonus for it, a fall 0.24 m from the in-hand position.

MuJoCo: elliptic friction cones with impratio 10, per-world buffers as measured under random actions
(see ``sim.mujoco``). Isaac Lab's OpenAI variants (asymmetric critic, domain randomization) are not here.
"""

from simlab.assets import ArticulationCfg, RigidObjectCfg
from simlab.envs import DirectRLEnvCfg, ViewerCfg
from simlab.markers import VisualizationMarkersCfg
from simlab.robots.dex_cube import dex_cube_cfg, dex_cube_marker_cfg
from simlab.robots.shadow_hand import SHADOW_HAND_CFG, SHADOW_HAND_COUPLED_JOINTS, SHADOW_HAND_FINGERTIP_BODIES
from simlab.scene import InteractiveSceneCfg
from simlab.sim import MujocoCfg, PhysxCfg, SimulationCfg
from simlab.sim.spawners.materials.physics_materials_cfg import RigidBodyMaterialCfg
from simlab.utils import configclass


@configclass
class ShadowHandEnvCfg(DirectRLEnvCfg):
    # env
    decimation = 2
    episode_length_s = 10.0
    action_space = 20
    observation_space = 157  # (full)
    state_space = 0
    asymmetric_obs = False
    obs_type = "full"

    # simulation
    sim: SimulationCfg = SimulationCfg(
        dt=1 / 120,
        render_interval=decimation,
        physics_material=RigidBodyMaterialCfg(static_friction=1.0, dynamic_friction=1.0),
        physx=PhysxCfg(bounce_threshold_velocity=0.2),
        # per world: peaks of 14 contacts and 84 constraint rows measured under random actions (8 worlds,
        # 150 steps; tests/test_inhand_manipulation.py), with room for more than twice that
        mujoco=MujocoCfg(cone="elliptic", impratio=10.0, nconmax=48, njmax=256),
    )
    # robot
    robot_cfg: ArticulationCfg = SHADOW_HAND_CFG.replace(prim_path="/World/envs/env_.*/Robot").replace(
        init_state=ArticulationCfg.InitialStateCfg(pos=(0.0, 0.0, 0.5), rot=(1.0, 0.0, 0.0, 0.0), joint_pos={".*": 0.0})
    )
    actuated_joint_names = [
        "robot0_WRJ1",
        "robot0_WRJ0",
        "robot0_FFJ3",
        "robot0_FFJ2",
        "robot0_FFJ1",
        "robot0_MFJ3",
        "robot0_MFJ2",
        "robot0_MFJ1",
        "robot0_RFJ3",
        "robot0_RFJ2",
        "robot0_RFJ1",
        "robot0_LFJ4",
        "robot0_LFJ3",
        "robot0_LFJ2",
        "robot0_LFJ1",
        "robot0_THJ4",
        "robot0_THJ3",
        "robot0_THJ2",
        "robot0_THJ1",
        "robot0_THJ0",
    ]
    coupled_joints: dict[str, str] = dict(SHADOW_HAND_COUPLED_JOINTS)
    """Joints the model couples to another (follower: leader); a reset draws only the leader's position."""
    fingertip_body_names = list(SHADOW_HAND_FINGERTIP_BODIES)

    # in-hand object: Isaac Lab's DexCube, density 567
    object_cfg: RigidObjectCfg = RigidObjectCfg(
        prim_path="/World/envs/env_.*/object",
        spawn=dex_cube_cfg(scale=1.0, density=567.0),
        init_state=RigidObjectCfg.InitialStateCfg(pos=(0.0, -0.39, 0.6), rot=(1.0, 0.0, 0.0, 0.0)),
    )
    # goal object
    goal_object_cfg: VisualizationMarkersCfg = VisualizationMarkersCfg(
        prim_path="/Visuals/goal_marker", markers={"goal": dex_cube_marker_cfg(scale=1.0)}
    )
    # scene
    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=8192, env_spacing=0.75, replicate_physics=True)
    # videos look at env 0's hand and the goal cube beside it
    viewer: ViewerCfg = ViewerCfg(eye=(0.5, 0.0, 0.95), lookat=(-0.1, -0.4, 0.55), origin_type="env")

    # reset
    reset_position_noise = 0.01  # range of position at reset
    reset_dof_pos_noise = 0.2  # range of dof pos at reset
    reset_dof_vel_noise = 0.0  # range of dof vel at reset
    # reward scales
    dist_reward_scale = -10.0
    rot_reward_scale = 1.0
    rot_eps = 0.1
    action_penalty_scale = -0.0002
    reach_goal_bonus = 250
    fall_penalty = 0
    fall_dist = 0.24
    vel_obs_scale = 0.2
    success_tolerance = 0.1
    max_consecutive_success = 0
    av_factor = 0.1
    act_moving_average = 1.0
    force_torque_obs_scale = 10.0
