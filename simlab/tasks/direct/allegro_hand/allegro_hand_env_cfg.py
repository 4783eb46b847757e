"""Allegro Hand cube reorientation, direct workflow (Isaac Lab's ``direct/allegro_hand``).

Isaac Lab's settings: 1/120 s physics, 4 physics steps per action, 10 s episodes, 16 actions, 124
observations ("full"), the cube (a 7.2 cm DexCube, 400 kg/m^3) dropped on the fingers of the palm-up
hand, a goal reached within 0.2 rad, a 250 bonus for it, a fall 0.24 m from the in-hand position.

MuJoCo: elliptic friction cones with impratio 10 (as Isaac Lab's own MuJoCo-Warp preset of this task),
so that fingertip friction holds a turning cube; per-world contact and constraint buffers sized from
the contacts counted under random actions (see ``sim.mujoco`` below).
"""

from simlab.assets import ArticulationCfg, RigidObjectCfg
from simlab.envs import DirectRLEnvCfg, ViewerCfg
from simlab.markers import VisualizationMarkersCfg
from simlab.robots.allegro import ALLEGRO_FINGERTIP_BODIES, ALLEGRO_HAND_CFG
from simlab.robots.dex_cube import dex_cube_cfg, dex_cube_marker_cfg
from simlab.scene import InteractiveSceneCfg
from simlab.sim import MujocoCfg, PhysxCfg, SimulationCfg
from simlab.sim.spawners.materials.physics_materials_cfg import RigidBodyMaterialCfg
from simlab.utils import configclass


@configclass
class AllegroHandEnvCfg(DirectRLEnvCfg):
    # env
    decimation = 4
    episode_length_s = 10.0
    action_space = 16
    observation_space = 124  # (full)
    state_space = 0
    asymmetric_obs = False
    obs_type = "full"
    # no extras["final_obs"]: this task's agents (rsl_rl, rl_games, skrl) do not read them, and they would
    # cost a second forward pass per step (the fingertips' poses before and after the resets), as Isaac Lab
    final_observations = False
    # simulation
    sim: SimulationCfg = SimulationCfg(
        dt=1 / 120,
        render_interval=decimation,
        physics_material=RigidBodyMaterialCfg(static_friction=1.0, dynamic_friction=1.0),
        physx=PhysxCfg(bounce_threshold_velocity=0.2),
        # per world: peaks of 13 contacts and 68 constraint rows measured under random actions (8 worlds,
        # 150 steps, the URDF's joint limits, kp 1; 23 and 108 at kp 3), 30 and 136 with the hand closed
        # on the cube (tests/test_inhand_manipulation.py): room for 1.5 times the worst
        mujoco=MujocoCfg(cone="elliptic", impratio=10.0, nconmax=48, njmax=256),
    )
    # robot
    robot_cfg: ArticulationCfg = ALLEGRO_HAND_CFG.replace(prim_path="/World/envs/env_.*/Robot")
    actuated_joint_names = [
        "index_joint_0",
        "middle_joint_0",
        "ring_joint_0",
        "thumb_joint_0",
        "index_joint_1",
        "index_joint_2",
        "index_joint_3",
        "middle_joint_1",
        "middle_joint_2",
        "middle_joint_3",
        "ring_joint_1",
        "ring_joint_2",
        "ring_joint_3",
        "thumb_joint_1",
        "thumb_joint_2",
        "thumb_joint_3",
    ]
    coupled_joints: dict[str, str] = {}
    """Joints the model couples to another (follower: leader); a reset draws only the leader's position."""
    fingertip_body_names = list(ALLEGRO_FINGERTIP_BODIES)

    # in-hand object: Isaac Lab's DexCube scaled 1.2, density 400
    object_cfg: RigidObjectCfg = RigidObjectCfg(
        prim_path="/World/envs/env_.*/object",
        spawn=dex_cube_cfg(scale=1.2, density=400.0),
        init_state=RigidObjectCfg.InitialStateCfg(pos=(0.0, -0.17, 0.56), rot=(1.0, 0.0, 0.0, 0.0)),
    )
    # goal object
    goal_object_cfg: VisualizationMarkersCfg = VisualizationMarkersCfg(
        prim_path="/Visuals/goal_marker", markers={"goal": dex_cube_marker_cfg(scale=1.2)}
    )
    # scene
    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=8192, env_spacing=0.75, replicate_physics=True)
    # videos look at env 0's hand and the goal cube beside it
    viewer: ViewerCfg = ViewerCfg(eye=(0.45, 0.25, 0.9), lookat=(-0.05, -0.25, 0.55), origin_type="env")
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
    success_tolerance = 0.2
    max_consecutive_success = 0
    av_factor = 0.1
    act_moving_average = 1.0
    force_torque_obs_scale = 10.0
