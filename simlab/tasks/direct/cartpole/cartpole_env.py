"""Cartpole, direct workflow (Isaac Lab's ``Isaac-Cartpole-Direct-v0``).

A force on the cart (``action * 100 N``) keeps the pole upright. Observations: pole angle, pole
velocity, cart position, cart velocity. An episode ends when the cart leaves +-3 m or the pole
falls past 90 degrees, or after 5 s.
"""

from __future__ import annotations

import math

import torch

import simlab.sim as sim_utils
from simlab.assets import Articulation, ArticulationCfg
from simlab.envs import DirectRLEnv, DirectRLEnvCfg
from simlab.robots.cartpole import CARTPOLE_CFG
from simlab.scene import InteractiveSceneCfg
from simlab.sim import SimulationCfg
from simlab.sim.spawners.from_files import GroundPlaneCfg, spawn_ground_plane
from simlab.utils import configclass
from simlab.utils.math import sample_uniform


@configclass
class CartpoleEnvCfg(DirectRLEnvCfg):
    # env
    decimation = 2
    episode_length_s = 5.0
    action_scale = 100.0  # [N]
    action_space = 1
    observation_space = 4
    state_space = 0

    # simulation
    sim: SimulationCfg = SimulationCfg(dt=1 / 120, render_interval=decimation)

    # robot
    robot_cfg: ArticulationCfg = CARTPOLE_CFG.replace(prim_path="/World/envs/env_.*/Robot")
    cart_dof_name = "slider_to_cart"
    pole_dof_name = "cart_to_pole"

    # scene
    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=4096, env_spacing=4.0, replicate_physics=True)

    # reset
    max_cart_pos = 3.0  # the cart is reset beyond this position [m]
    initial_pole_angle_range = [-0.25, 0.25]  # pole angle at reset, in units of pi [rad / pi]

    # reward scales
    rew_scale_alive = 1.0
    rew_scale_terminated = -2.0
    rew_scale_pole_pos = -1.0
    rew_scale_cart_vel = -0.01
    rew_scale_pole_vel = -0.005


class CartpoleEnv(DirectRLEnv):
    cfg: CartpoleEnvCfg

    def __init__(self, cfg: CartpoleEnvCfg, render_mode: str | None = None, **kwargs):
        super().__init__(cfg, render_mode, **kwargs)
        self._cart_dof_idx, _ = self.cartpole.find_joints(self.cfg.cart_dof_name)
        self._pole_dof_idx, _ = self.cartpole.find_joints(self.cfg.pole_dof_name)
        self.action_scale = self.cfg.action_scale

    def _setup_scene(self):
        self.cartpole = Articulation(self.cfg.robot_cfg)
        spawn_ground_plane(prim_path="/World/ground", cfg=GroundPlaneCfg())
        self.scene.articulations["cartpole"] = self.cartpole
        light_cfg = sim_utils.DomeLightCfg(intensity=2000.0, color=(0.75, 0.75, 0.75))
        light_cfg.func("/World/Light", light_cfg)

    def _pre_physics_step(self, actions: torch.Tensor) -> None:
        self.actions = self.action_scale * actions.clone()

    def _apply_action(self) -> None:
        self.cartpole.set_joint_effort_target(self.actions, joint_ids=self._cart_dof_idx)

    @property
    def joint_pos(self) -> torch.Tensor:
        """The joint positions (num_envs, 2) now (Isaac Lab's attribute, read by its subclasses)."""
        return self.cartpole.data.joint_pos

    @property
    def joint_vel(self) -> torch.Tensor:
        """The joint velocities (num_envs, 2) now."""
        return self.cartpole.data.joint_vel

    def _joint_states(self) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor]:
        """Pole angle, pole velocity, cart position, cart velocity; each (num_envs,)."""
        joint_pos, joint_vel = self.cartpole.data.joint_pos, self.cartpole.data.joint_vel
        pole, cart = self._pole_dof_idx[0], self._cart_dof_idx[0]
        return joint_pos[:, pole], joint_vel[:, pole], joint_pos[:, cart], joint_vel[:, cart]

    def _get_observations(self) -> dict:
        return {"policy": torch.stack(self._joint_states(), dim=-1)}

    def _get_rewards(self) -> torch.Tensor:
        pole_pos, pole_vel, cart_pos, cart_vel = self._joint_states()
        return compute_rewards(
            self.cfg.rew_scale_alive,
            self.cfg.rew_scale_terminated,
            self.cfg.rew_scale_pole_pos,
            self.cfg.rew_scale_cart_vel,
            self.cfg.rew_scale_pole_vel,
            pole_pos,
            pole_vel,
            cart_pos,
            cart_vel,
            self.reset_terminated,
        )

    def _get_dones(self) -> tuple[torch.Tensor, torch.Tensor]:
        pole_pos, _, cart_pos, _ = self._joint_states()
        time_out = self.episode_length_buf >= self.max_episode_length - 1
        out_of_bounds = (torch.abs(cart_pos) > self.cfg.max_cart_pos) | (torch.abs(pole_pos) > math.pi / 2)
        return out_of_bounds, time_out

    def _reset_mask(self, env_mask: torch.Tensor):
        super()._reset_mask(env_mask)
        # Initial states are drawn for every env and written where env_mask is set.
        joint_pos = self.cartpole.data.default_joint_pos.clone()
        joint_pos[:, self._pole_dof_idx] += sample_uniform(
            self.cfg.initial_pole_angle_range[0] * math.pi,
            self.cfg.initial_pole_angle_range[1] * math.pi,
            joint_pos[:, self._pole_dof_idx].shape,
            joint_pos.device,
        )
        joint_vel = self.cartpole.data.default_joint_vel.clone()
        default_root_state = self.cartpole.data.default_root_state.clone()
        default_root_state[:, :3] += self.scene.env_origins

        self.cartpole.write_root_pose_to_sim(default_root_state[:, :7], env_mask)
        self.cartpole.write_root_velocity_to_sim(default_root_state[:, 7:], env_mask)
        self.cartpole.write_joint_state_to_sim(joint_pos, joint_vel, None, env_mask)


@torch.jit.script
def compute_rewards(
    rew_scale_alive: float,
    rew_scale_terminated: float,
    rew_scale_pole_pos: float,
    rew_scale_cart_vel: float,
    rew_scale_pole_vel: float,
    pole_pos: torch.Tensor,
    pole_vel: torch.Tensor,
    cart_pos: torch.Tensor,
    cart_vel: torch.Tensor,
    reset_terminated: torch.Tensor,
):
    rew_alive = rew_scale_alive * (1.0 - reset_terminated.float())
    rew_termination = rew_scale_terminated * reset_terminated.float()
    rew_pole_pos = rew_scale_pole_pos * torch.sum(torch.square(pole_pos).unsqueeze(dim=1), dim=-1)
    rew_cart_vel = rew_scale_cart_vel * torch.sum(torch.abs(cart_vel).unsqueeze(dim=1), dim=-1)
    rew_pole_vel = rew_scale_pole_vel * torch.sum(torch.abs(pole_vel).unsqueeze(dim=1), dim=-1)
    total_reward = rew_alive + rew_termination + rew_pole_pos + rew_cart_vel + rew_pole_vel
    return total_reward
