"""Two Shadow Hands pass a ball, direct multi-agent workflow (Isaac Lab's ``direct/shadow_hand_over``).

Isaac Lab's settings: 1/120 s physics, 2 physics steps per action, 7.5 s episodes, agents
"right_hand" and "left_hand" with 20 actions and 157 observations each and a 290-value shared state;
the right hand palm up at the origin, the left one turned half a turn about z, 1 m away along -y, so
the two face each other fingers first; a 3.35 cm ball (500 kg/m^3) starts on the right palm, its goal
is above the left palm; the episode ends when the ball drops below 0.24 m.

MuJoCo: elliptic friction cones with impratio 10, per-world buffers as measured under random actions
(see ``sim.mujoco``). Isaac Lab's file declares a domain-randomization ``EventCfg`` but its env config
does not use it; neither does this one.
"""

import simlab.sim as sim_utils
from simlab.assets import ArticulationCfg, RigidObjectCfg
from simlab.envs import DirectMARLEnvCfg, ViewerCfg
from simlab.markers import VisualizationMarkersCfg
from simlab.robots.shadow_hand import SHADOW_HAND_CFG, SHADOW_HAND_COUPLED_JOINTS, SHADOW_HAND_FINGERTIP_BODIES
from simlab.scene import InteractiveSceneCfg
from simlab.sim import MujocoCfg, PhysxCfg, SimulationCfg
from simlab.sim.spawners.materials.physics_materials_cfg import RigidBodyMaterialCfg
from simlab.tasks.direct.shadow_hand.shadow_hand_env_cfg import ShadowHandEnvCfg
from simlab.utils import configclass


@configclass
class ShadowHandOverEnvCfg(DirectMARLEnvCfg):
    # env
    decimation = 2
    episode_length_s = 7.5
    possible_agents = ["right_hand", "left_hand"]
    action_spaces = {"right_hand": 20, "left_hand": 20}
    observation_spaces = {"right_hand": 157, "left_hand": 157}
    state_space = 290

    # simulation
    sim: SimulationCfg = SimulationCfg(
        dt=1 / 120,
        render_interval=decimation,
        physics_material=RigidBodyMaterialCfg(static_friction=1.0, dynamic_friction=1.0),
        physx=PhysxCfg(bounce_threshold_velocity=0.2),
        # per world: peaks of 12 contacts and 104 constraint rows measured under random actions (4 worlds,
        # 60 steps, 0.5 s episodes; tests/test_shadow_hand_over.py), with room for more than twice that
        mujoco=MujocoCfg(cone="elliptic", impratio=10.0, nconmax=48, njmax=256),
    )
    # robots
    right_robot_cfg: ArticulationCfg = SHADOW_HAND_CFG.replace(prim_path="/World/envs/env_.*/RightRobot").replace(
        init_state=ArticulationCfg.InitialStateCfg(pos=(0.0, 0.0, 0.5), rot=(1.0, 0.0, 0.0, 0.0), joint_pos={".*": 0.0})
    )
    left_robot_cfg: ArticulationCfg = SHADOW_HAND_CFG.replace(prim_path="/World/envs/env_.*/LeftRobot").replace(
        init_state=ArticulationCfg.InitialStateCfg(
            pos=(0.0, -1.0, 0.5), rot=(0.0, 0.0, 0.0, 1.0), joint_pos={".*": 0.0}
        )
    )
    actuated_joint_names = list(ShadowHandEnvCfg().actuated_joint_names)
    coupled_joints: dict[str, str] = dict(SHADOW_HAND_COUPLED_JOINTS)
    """Joints the model couples to another (follower: leader); a reset draws only the leader's position."""
    fingertip_body_names = list(SHADOW_HAND_FINGERTIP_BODIES)

    # the ball
    object_cfg: RigidObjectCfg = RigidObjectCfg(
        prim_path="/World/envs/env_.*/object",
        spawn=sim_utils.SphereCfg(
            radius=0.0335,
            visual_material=sim_utils.PreviewSurfaceCfg(diffuse_color=(0.8, 1.0, 0.0)),
            physics_material=sim_utils.RigidBodyMaterialCfg(static_friction=0.7),
            rigid_props=sim_utils.RigidBodyPropertiesCfg(
                kinematic_enabled=False,
                disable_gravity=False,
                enable_gyroscopic_forces=True,
                solver_position_iteration_count=8,
                solver_velocity_iteration_count=0,
                sleep_threshold=0.005,
                stabilization_threshold=0.0025,
                max_depenetration_velocity=1000.0,
            ),
            collision_props=sim_utils.CollisionPropertiesCfg(),
            mass_props=sim_utils.MassPropertiesCfg(density=500.0),
        ),
        init_state=RigidObjectCfg.InitialStateCfg(pos=(0.0, -0.39, 0.54), rot=(1.0, 0.0, 0.0, 0.0)),
    )
    # goal marker
    goal_object_cfg: VisualizationMarkersCfg = VisualizationMarkersCfg(
        prim_path="/Visuals/goal_marker",
        markers={
            "goal": sim_utils.SphereCfg(
                radius=0.0335, visual_material=sim_utils.PreviewSurfaceCfg(diffuse_color=(0.4, 0.3, 1.0))
            )
        },
    )
    goal_pos = (0.0, -0.64, 0.54)
    """The goal, in each env's frame: above the left palm."""
    # scene
    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=2048, env_spacing=1.5, replicate_physics=True)
    # videos look at env 0's two hands from the side
    viewer: ViewerCfg = ViewerCfg(eye=(1.0, -0.5, 1.0), lookat=(0.0, -0.5, 0.5), origin_type="env")

    # reset
    reset_position_noise = 0.01  # range of position at reset
    reset_dof_pos_noise = 0.2  # range of dof pos at reset
    reset_dof_vel_noise = 0.0  # range of dof vel at reset
    # scales and constants
    fall_dist = 0.24
    vel_obs_scale = 0.2
    act_moving_average = 1.0
    # reward-related scales
    dist_reward_scale = 20.0
    catch_radius = 0.05
    """simlab's: a ball within this distance [m] of the goal counts as caught (the solve criterion)."""
