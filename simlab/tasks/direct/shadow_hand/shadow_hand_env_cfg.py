"""Shadow Hand cube reorientation, direct workflow (Isaac Lab's ``direct/shadow_hand``).

Isaac Lab's settings: 1/120 s physics, 2 physics steps per action, 10 s episodes, 20 actions (the
coupled distal joints follow), 157 observations ("full"), a 6 cm DexCube (567 kg/m^3) dropped on the
palm-up hand, a goal reached within 0.1 rad, a 250 bonus for it, a fall 0.24 m from the in-hand position.

MuJoCo: elliptic friction cones with impratio 10, per-world buffers as measured under random actions
(see ``sim.mujoco``).

``ShadowHandOpenAIEnvCfg`` is Isaac Lab's OpenAI variant (arXiv:1808.00177): 1/60 s physics, 3 physics
steps per action, 8 s episodes, a 42-value policy observation ("openai") and a 187-value critic state
(the full observations and the fingertips' force-torque readings), a goal within 0.4 rad, a -50 fall
penalty, 50 goals at most per episode, Gaussian action and observation noise with a per-episode bias,
and Isaac Lab's domain randomization (friction, joint gains and limits, cube mass, gravity; its fixed
tendon randomization is accepted and ignored: the coupling here is an equality constraint).
"""

import simlab.envs.mdp as mdp
from simlab.assets import ArticulationCfg, RigidObjectCfg
from simlab.envs import DirectRLEnvCfg, ViewerCfg
from simlab.managers import EventTermCfg as EventTerm
from simlab.managers import SceneEntityCfg
from simlab.markers import VisualizationMarkersCfg
from simlab.robots.dex_cube import dex_cube_cfg, dex_cube_marker_cfg
from simlab.robots.shadow_hand import SHADOW_HAND_CFG, SHADOW_HAND_COUPLED_JOINTS, SHADOW_HAND_FINGERTIP_BODIES
from simlab.scene import InteractiveSceneCfg
from simlab.sim import MujocoCfg, PhysxCfg, SimulationCfg
from simlab.sim.spawners.materials.physics_materials_cfg import RigidBodyMaterialCfg
from simlab.utils import configclass
from simlab.utils.noise import GaussianNoiseCfg, NoiseModelWithAdditiveBiasCfg


def _every_720_resets(func, **params) -> EventTerm:
    """A reset randomization redrawn at most every 720 env steps (Isaac Lab's OpenAI settings)."""
    return EventTerm(func=func, mode="reset", min_step_count_between_reset=720, params=params)


@configclass
class EventCfg:
    """Isaac Lab's domain randomization for the OpenAI variant."""

    robot_physics_material = _every_720_resets(
        mdp.randomize_rigid_body_material,
        asset_cfg=SceneEntityCfg("robot"),
        static_friction_range=(0.7, 1.3),
        dynamic_friction_range=(1.0, 1.0),
        restitution_range=(1.0, 1.0),
        num_buckets=250,
    )
    robot_joint_stiffness_and_damping = _every_720_resets(
        mdp.randomize_actuator_gains,
        asset_cfg=SceneEntityCfg("robot", joint_names=".*"),
        stiffness_distribution_params=(0.75, 1.5),
        damping_distribution_params=(0.3, 3.0),
        operation="scale",
        distribution="log_uniform",
    )
    robot_joint_limits = _every_720_resets(
        mdp.randomize_joint_parameters,
        asset_cfg=SceneEntityCfg("robot", joint_names=".*"),
        lower_limit_distribution_params=(0.00, 0.01),
        upper_limit_distribution_params=(0.00, 0.01),
        operation="add",
        distribution="gaussian",
    )
    robot_tendon_properties = _every_720_resets(
        mdp.randomize_fixed_tendon_parameters,  # accepted and ignored (see the module docstring)
        asset_cfg=SceneEntityCfg("robot", fixed_tendon_names=".*"),
        stiffness_distribution_params=(0.75, 1.5),
        damping_distribution_params=(0.3, 3.0),
        operation="scale",
        distribution="log_uniform",
    )
    object_physics_material = _every_720_resets(
        mdp.randomize_rigid_body_material,
        asset_cfg=SceneEntityCfg("object"),
        static_friction_range=(0.7, 1.3),
        dynamic_friction_range=(1.0, 1.0),
        restitution_range=(1.0, 1.0),
        num_buckets=250,
    )
    object_scale_mass = _every_720_resets(
        mdp.randomize_rigid_body_mass,
        asset_cfg=SceneEntityCfg("object"),
        mass_distribution_params=(0.5, 1.5),
        operation="scale",
        distribution="uniform",
    )
    reset_gravity = EventTerm(
        func=mdp.randomize_physics_scene_gravity,
        mode="interval",
        is_global_time=True,
        interval_range_s=(36.0, 36.0),  # time_s = num_steps * (decimation * dt)
        params={
            "gravity_distribution_params": ([0.0, 0.0, 0.0], [0.0, 0.0, 0.4]),
            "operation": "add",
            "distribution": "gaussian",
        },
    )


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
    # no extras["final_obs"]: this task's agents (rsl_rl, rl_games, skrl) do not read them, and they would
    # cost a second forward pass per step (the fingertips' poses before and after the resets), as Isaac Lab
    final_observations = False

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


@configclass
class ShadowHandOpenAIEnvCfg(ShadowHandEnvCfg):
    # env
    decimation = 3
    episode_length_s = 8.0
    action_space = 20
    observation_space = 42
    state_space = 187
    asymmetric_obs = True
    obs_type = "openai"
    # simulation
    sim: SimulationCfg = SimulationCfg(
        dt=1 / 60,
        render_interval=decimation,
        physics_material=RigidBodyMaterialCfg(static_friction=1.0, dynamic_friction=1.0),
        physx=PhysxCfg(
            bounce_threshold_velocity=0.2, gpu_max_rigid_contact_count=2**23, gpu_max_rigid_patch_count=2**23
        ),
        # per world: peaks of 23 contacts and 120 constraint rows measured under random actions (4 worlds,
        # 60 steps, 0.5 s episodes; tests/test_shadow_openai.py), with room for more than twice that
        mujoco=MujocoCfg(cone="elliptic", impratio=10.0, nconmax=64, njmax=384),
    )
    # reset
    reset_position_noise = 0.01
    reset_dof_pos_noise = 0.2
    reset_dof_vel_noise = 0.0
    # reward scales
    dist_reward_scale = -10.0
    rot_reward_scale = 1.0
    rot_eps = 0.1
    action_penalty_scale = -0.0002
    reach_goal_bonus = 250
    fall_penalty = -50
    fall_dist = 0.24
    vel_obs_scale = 0.2
    success_tolerance = 0.4
    max_consecutive_success = 50
    av_factor = 0.1
    act_moving_average = 0.3
    force_torque_obs_scale = 10.0
    # domain randomization
    events: EventCfg = EventCfg()
    # Gaussian noise each step plus a Gaussian bias drawn per env at reset
    action_noise_model: NoiseModelWithAdditiveBiasCfg = NoiseModelWithAdditiveBiasCfg(
        noise_cfg=GaussianNoiseCfg(mean=0.0, std=0.05, operation="add"),
        bias_noise_cfg=GaussianNoiseCfg(mean=0.0, std=0.015, operation="abs"),
    )
    observation_noise_model: NoiseModelWithAdditiveBiasCfg = NoiseModelWithAdditiveBiasCfg(
        noise_cfg=GaussianNoiseCfg(mean=0.0, std=0.002, operation="add"),
        bias_noise_cfg=GaussianNoiseCfg(mean=0.0, std=0.0001, operation="abs"),
    )
