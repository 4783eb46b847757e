"""Ant, direct workflow (Isaac Lab's ``Isaac-Ant-Direct-v0``): run forward without falling.

8 torque-driven joints (``0.5 * 15 * action``), 36 observations, 15 s episodes; the episode ends
when the torso drops below 0.31 m. See :mod:`simlab.tasks.direct.locomotion.locomotion_env`.
"""

from __future__ import annotations

import simlab.sim as sim_utils
from simlab.assets import ArticulationCfg
from simlab.envs import DirectRLEnvCfg
from simlab.robots.ant import ANT_CFG
from simlab.scene import InteractiveSceneCfg
from simlab.sim import MujocoCfg, SimulationCfg
from simlab.sim.spawners.from_files import GroundPlaneCfg
from simlab.tasks.direct.locomotion.locomotion_env import LocomotionEnv
from simlab.utils import configclass


@configclass
class AntEnvCfg(DirectRLEnvCfg):
    # env
    episode_length_s = 15.0
    decimation = 2
    action_scale = 0.5
    action_space = 8
    observation_space = 36
    state_space = 0

    # simulation: the legs touch only the ground
    sim: SimulationCfg = SimulationCfg(dt=1 / 120, render_interval=decimation, mujoco=MujocoCfg(nconmax=32, njmax=160))
    terrain = GroundPlaneCfg(
        physics_material=sim_utils.RigidBodyMaterialCfg(static_friction=1.0, dynamic_friction=1.0, restitution=0.0)
    )

    # scene
    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=4096, env_spacing=4.0, replicate_physics=True)

    # robot
    robot: ArticulationCfg = ANT_CFG.replace(prim_path="/World/envs/env_.*/Robot")
    joint_gears: list = [15, 15, 15, 15, 15, 15, 15, 15]

    heading_weight: float = 0.5
    up_weight: float = 0.1

    energy_cost_scale: float = 0.05
    actions_cost_scale: float = 0.005
    alive_reward_scale: float = 0.5
    dof_vel_scale: float = 0.2

    death_cost: float = -2.0
    termination_height: float = 0.31

    angular_velocity_scale: float = 1.0
    contact_force_scale: float = 0.1


class AntEnv(LocomotionEnv):
    cfg: AntEnvCfg

    def __init__(self, cfg: AntEnvCfg, render_mode: str | None = None, **kwargs):
        super().__init__(cfg, render_mode, **kwargs)
