"""Cart double pendulum, direct multi-agent workflow (Isaac Lab's ``Isaac-Cart-Double-Pendulum-Direct-v0``).

Two agents share each environment: ``cart`` pushes the cart (``action * 100 N``) and ``pendulum``
drives the joint between pole and pendulum (``action * 50 N m``). Both are rewarded for keeping the
pole and the pendulum upright; the episode ends when the cart leaves +-3 m or the pole falls past
90 degrees, or after 5 s. The shared state (``state_space=-1``) concatenates both observations.
"""

from __future__ import annotations

import math

import torch

import simlab.sim as sim_utils
from simlab.assets import Articulation, ArticulationCfg
from simlab.envs import DirectMARLEnv, DirectMARLEnvCfg
from simlab.robots.cart_double_pendulum import CART_DOUBLE_PENDULUM_CFG
from simlab.scene import InteractiveSceneCfg
from simlab.sim import SimulationCfg
from simlab.sim.spawners.from_files import GroundPlaneCfg, spawn_ground_plane
from simlab.utils import configclass
from simlab.utils.math import sample_uniform


@configclass
class CartDoublePendulumEnvCfg(DirectMARLEnvCfg):
    # env
    decimation = 2
    episode_length_s = 5.0
    possible_agents = ["cart", "pendulum"]
    action_spaces = {"cart": 1, "pendulum": 1}
    observation_spaces = {"cart": 4, "pendulum": 3}
    state_space = -1

    # simulation
    sim: SimulationCfg = SimulationCfg(dt=1 / 120, render_interval=decimation)

    # robot
    robot_cfg: ArticulationCfg = CART_DOUBLE_PENDULUM_CFG.replace(prim_path="/World/envs/env_.*/Robot")
    cart_dof_name = "slider_to_cart"
    pole_dof_name = "cart_to_pole"
    pendulum_dof_name = "pole_to_pendulum"

    # scene
    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=4096, env_spacing=4.0, replicate_physics=True)

    # reset
    max_cart_pos = 3.0  # the cart is reset beyond this position [m]
    initial_pole_angle_range = [-0.25, 0.25]  # pole angle at reset, in units of pi [rad / pi]
    initial_pendulum_angle_range = [-0.25, 0.25]  # pendulum angle at reset, in units of pi [rad / pi]

    # action scales
    cart_action_scale = 100.0  # [N]
    pendulum_action_scale = 50.0  # [Nm]

    # reward scales
    rew_scale_alive = 1.0
    rew_scale_terminated = -2.0
    rew_scale_cart_pos = 0
    rew_scale_cart_vel = -0.01
    rew_scale_pole_pos = -1.0
    rew_scale_pole_vel = -0.01
    rew_scale_pendulum_pos = -1.0
    rew_scale_pendulum_vel = -0.01


class CartDoublePendulumEnv(DirectMARLEnv):
    cfg: CartDoublePendulumEnvCfg

    def __init__(self, cfg: CartDoublePendulumEnvCfg, render_mode: str | None = None, **kwargs):
        super().__init__(cfg, render_mode, **kwargs)
        self._cart_dof_idx, _ = self.robot.find_joints(self.cfg.cart_dof_name)
        self._pole_dof_idx, _ = self.robot.find_joints(self.cfg.pole_dof_name)
        self._pendulum_dof_idx, _ = self.robot.find_joints(self.cfg.pendulum_dof_name)

    def _setup_scene(self):
        self.robot = Articulation(self.cfg.robot_cfg)
        spawn_ground_plane(prim_path="/World/ground", cfg=GroundPlaneCfg())
        self.scene.articulations["robot"] = self.robot
        light_cfg = sim_utils.DomeLightCfg(intensity=2000.0, color=(0.75, 0.75, 0.75))
        light_cfg.func("/World/Light", light_cfg)

    def _pre_physics_step(self, actions: dict[str, torch.Tensor]) -> None:
        self.actions = actions

    def _apply_action(self) -> None:
        self.robot.set_joint_effort_target(
            self.actions["cart"] * self.cfg.cart_action_scale, joint_ids=self._cart_dof_idx
        )
        self.robot.set_joint_effort_target(
            self.actions["pendulum"] * self.cfg.pendulum_action_scale, joint_ids=self._pendulum_dof_idx
        )

    def _get_observations(self) -> dict[str, torch.Tensor]:
        joint_pos, joint_vel = self.robot.data.joint_pos, self.robot.data.joint_vel
        cart, pole, pendulum = self._cart_dof_idx[0], self._pole_dof_idx[0], self._pendulum_dof_idx[0]
        pole_joint_pos = normalize_angle(joint_pos[:, pole].unsqueeze(dim=1))
        pendulum_joint_pos = normalize_angle(joint_pos[:, pendulum].unsqueeze(dim=1))
        return {
            "cart": torch.cat(
                (
                    joint_pos[:, cart].unsqueeze(dim=1),
                    joint_vel[:, cart].unsqueeze(dim=1),
                    pole_joint_pos,
                    joint_vel[:, pole].unsqueeze(dim=1),
                ),
                dim=-1,
            ),
            "pendulum": torch.cat(
                (
                    pole_joint_pos + pendulum_joint_pos,
                    pendulum_joint_pos,
                    joint_vel[:, pendulum].unsqueeze(dim=1),
                ),
                dim=-1,
            ),
        }

    def _get_rewards(self) -> dict[str, torch.Tensor]:
        joint_pos, joint_vel = self.robot.data.joint_pos, self.robot.data.joint_vel
        cart, pole, pendulum = self._cart_dof_idx[0], self._pole_dof_idx[0], self._pendulum_dof_idx[0]
        terminated = self.terminated_dict["cart"] & self.terminated_dict["pendulum"]
        return compute_rewards(
            self.cfg.rew_scale_alive,
            self.cfg.rew_scale_terminated,
            self.cfg.rew_scale_cart_pos,
            self.cfg.rew_scale_cart_vel,
            self.cfg.rew_scale_pole_pos,
            self.cfg.rew_scale_pole_vel,
            self.cfg.rew_scale_pendulum_pos,
            self.cfg.rew_scale_pendulum_vel,
            joint_pos[:, cart],
            joint_vel[:, cart],
            normalize_angle(joint_pos[:, pole]),
            joint_vel[:, pole],
            normalize_angle(joint_pos[:, pendulum]),
            joint_vel[:, pendulum],
            terminated,
        )

    def _get_dones(self) -> tuple[dict[str, torch.Tensor], dict[str, torch.Tensor]]:
        joint_pos = self.robot.data.joint_pos
        time_out = self.episode_length_buf >= self.max_episode_length - 1
        out_of_bounds = torch.abs(joint_pos[:, self._cart_dof_idx[0]]) > self.cfg.max_cart_pos
        out_of_bounds = out_of_bounds | (torch.abs(joint_pos[:, self._pole_dof_idx[0]]) > math.pi / 2)
        terminated = {agent: out_of_bounds for agent in self.cfg.possible_agents}
        time_outs = {agent: time_out for agent in self.cfg.possible_agents}
        return terminated, time_outs

    def _reset_mask(self, env_mask: torch.Tensor):
        super()._reset_mask(env_mask)
        # Initial states are drawn for every env and written where env_mask is set.
        joint_pos = self.robot.data.default_joint_pos.clone()
        joint_pos[:, self._pole_dof_idx] += sample_uniform(
            self.cfg.initial_pole_angle_range[0] * math.pi,
            self.cfg.initial_pole_angle_range[1] * math.pi,
            joint_pos[:, self._pole_dof_idx].shape,
            joint_pos.device,
        )
        joint_pos[:, self._pendulum_dof_idx] += sample_uniform(
            self.cfg.initial_pendulum_angle_range[0] * math.pi,
            self.cfg.initial_pendulum_angle_range[1] * math.pi,
            joint_pos[:, self._pendulum_dof_idx].shape,
            joint_pos.device,
        )
        joint_vel = self.robot.data.default_joint_vel.clone()
        default_root_state = self.robot.data.default_root_state.clone()
        default_root_state[:, :3] += self.scene.env_origins

        self.robot.write_root_pose_to_sim(default_root_state[:, :7], env_mask)
        self.robot.write_root_velocity_to_sim(default_root_state[:, 7:], env_mask)
        self.robot.write_joint_state_to_sim(joint_pos, joint_vel, None, env_mask)


@torch.jit.script
def normalize_angle(angle):
    return (angle + math.pi) % (2 * math.pi) - math.pi


@torch.jit.script
def compute_rewards(
    rew_scale_alive: float,
    rew_scale_terminated: float,
    rew_scale_cart_pos: float,
    rew_scale_cart_vel: float,
    rew_scale_pole_pos: float,
    rew_scale_pole_vel: float,
    rew_scale_pendulum_pos: float,
    rew_scale_pendulum_vel: float,
    cart_pos: torch.Tensor,
    cart_vel: torch.Tensor,
    pole_pos: torch.Tensor,
    pole_vel: torch.Tensor,
    pendulum_pos: torch.Tensor,
    pendulum_vel: torch.Tensor,
    reset_terminated: torch.Tensor,
):
    rew_alive = rew_scale_alive * (1.0 - reset_terminated.float())
    rew_termination = rew_scale_terminated * reset_terminated.float()
    rew_pole_pos = rew_scale_pole_pos * torch.sum(torch.square(pole_pos).unsqueeze(dim=1), dim=-1)
    rew_pendulum_pos = rew_scale_pendulum_pos * torch.sum(
        torch.square(pole_pos + pendulum_pos).unsqueeze(dim=1), dim=-1
    )
    rew_cart_vel = rew_scale_cart_vel * torch.sum(torch.abs(cart_vel).unsqueeze(dim=1), dim=-1)
    rew_pole_vel = rew_scale_pole_vel * torch.sum(torch.abs(pole_vel).unsqueeze(dim=1), dim=-1)
    rew_pendulum_vel = rew_scale_pendulum_vel * torch.sum(torch.abs(pendulum_vel).unsqueeze(dim=1), dim=-1)

    total_reward = {
        "cart": rew_alive + rew_termination + rew_pole_pos + rew_cart_vel + rew_pole_vel,
        "pendulum": rew_alive + rew_termination + rew_pendulum_pos + rew_pendulum_vel,
    }
    return total_reward
