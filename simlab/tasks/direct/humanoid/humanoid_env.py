"""Humanoid, direct workflow (Isaac Lab's ``Isaac-Humanoid-Direct-v0``): run forward without falling.

21 torque-driven joints (``gear * action``), 75 observations, 15 s episodes; the episode ends when
the torso drops below 0.8 m. See :mod:`simlab.tasks.direct.locomotion.locomotion_env`.
"""

from __future__ import annotations

import simlab.sim as sim_utils
from simlab.assets import ArticulationCfg
from simlab.envs import DirectRLEnvCfg
from simlab.robots.humanoid import HUMANOID_CFG
from simlab.scene import InteractiveSceneCfg
from simlab.sim import MujocoCfg, SimulationCfg
from simlab.sim.spawners.from_files import GroundPlaneCfg
from simlab.tasks.direct.locomotion.locomotion_env import LocomotionEnv
from simlab.utils import configclass


@configclass
class HumanoidEnvCfg(DirectRLEnvCfg):
    # env
    episode_length_s = 15.0
    decimation = 2
    action_scale = 1.0
    action_space = 21
    observation_space = 75
    state_space = 0

    # simulation: a lying humanoid touches the ground and itself at a few dozen points
    sim: SimulationCfg = SimulationCfg(dt=1 / 120, render_interval=decimation, mujoco=MujocoCfg(nconmax=64, njmax=320))
    terrain = GroundPlaneCfg(
        physics_material=sim_utils.RigidBodyMaterialCfg(static_friction=1.0, dynamic_friction=1.0, restitution=0.0)
    )

    # scene
    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=4096, env_spacing=4.0, replicate_physics=True)

    # robot
    robot: ArticulationCfg = HUMANOID_CFG.replace(prim_path="/World/envs/env_.*/Robot")
    # gears of the MuJoCo humanoid, by joint name (simlab's joint order is MuJoCo's, not Isaac Lab's)
    joint_gears: dict = {
        "lower_waist:.*": 67.5,
        "pelvis": 67.5,
        ".*_upper_arm:.*": 67.5,
        ".*_lower_arm": 45.0,
        ".*_thigh:0": 45.0,
        ".*_thigh:1": 135.0,
        ".*_thigh:2": 45.0,
        ".*_shin": 90.0,
        ".*_foot:.*": 22.5,
    }

    heading_weight: float = 0.5
    up_weight: float = 0.1

    energy_cost_scale: float = 0.05
    actions_cost_scale: float = 0.01
    alive_reward_scale: float = 2.0
    dof_vel_scale: float = 0.1

    death_cost: float = -1.0
    termination_height: float = 0.8

    angular_velocity_scale: float = 0.25
    contact_force_scale: float = 0.01


class HumanoidEnv(LocomotionEnv):
    cfg: HumanoidEnvCfg

    def __init__(self, cfg: HumanoidEnvCfg, render_mode: str | None = None, **kwargs):
        super().__init__(cfg, render_mode, **kwargs)
