"""Quadcopter, direct workflow (Isaac Lab's ``Isaac-Quadcopter-Direct-v0``): fly a Crazyflie to a goal.

Actions (4, clamped to [-1, 1]): total thrust ``thrust_to_weight * weight * (a0 + 1) / 2`` along the
body z axis and body moments ``moment_scale * a1:4`` [N m], applied to the body as an external
wrench every physics step. Observations (12): body-frame linear and angular velocity, gravity in
the body frame, the goal in the body frame. Goals are drawn 2 m around the env origin at 0.5-1.5 m
height. The episode ends when the drone leaves 0.1-2.0 m height, or after 10 s.
"""

from __future__ import annotations

import torch

import simlab.sim as sim_utils
from simlab.assets import Articulation, ArticulationCfg
from simlab.envs import DirectRLEnv, DirectRLEnvCfg
from simlab.robots.quadcopter import CRAZYFLIE_CFG
from simlab.scene import InteractiveSceneCfg
from simlab.sim import SimulationCfg
from simlab.sim.spawners.from_files import GroundPlaneCfg, spawn_ground_plane
from simlab.utils import configclass
from simlab.utils.env_mask import masked_copy_
from simlab.utils.math import subtract_frame_transforms

REWARD_TERMS = ("lin_vel", "ang_vel", "distance_to_goal")


@configclass
class QuadcopterEnvCfg(DirectRLEnvCfg):
    # env
    episode_length_s = 10.0
    decimation = 2
    action_space = 4
    observation_space = 12
    state_space = 0
    debug_vis = False  # goal markers need a viewer

    # simulation
    # CRAZYFLIE_CFG's enable_gyroscopic_forces makes the scene integrate with MuJoCo's "implicit" integrator
    sim: SimulationCfg = SimulationCfg(dt=1 / 100, render_interval=decimation)
    terrain = GroundPlaneCfg(
        physics_material=sim_utils.RigidBodyMaterialCfg(static_friction=1.0, dynamic_friction=1.0, restitution=0.0)
    )

    # scene
    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=4096, env_spacing=2.5, replicate_physics=True)

    # robot
    robot: ArticulationCfg = CRAZYFLIE_CFG.replace(prim_path="/World/envs/env_.*/Robot")
    thrust_to_weight = 1.9
    moment_scale = 0.01  # [N m] per unit action

    # reward scales
    lin_vel_reward_scale = -0.05
    ang_vel_reward_scale = -0.01
    distance_to_goal_reward_scale = 15.0


class QuadcopterEnv(DirectRLEnv):
    cfg: QuadcopterEnvCfg

    def __init__(self, cfg: QuadcopterEnvCfg, render_mode: str | None = None, **kwargs):
        super().__init__(cfg, render_mode, **kwargs)
        # Total thrust and moment applied to the body of the quadcopter
        self._actions = torch.zeros(self.num_envs, self.cfg.action_space, device=self.device)
        self._thrust = torch.zeros(self.num_envs, 1, 3, device=self.device)
        self._moment = torch.zeros(self.num_envs, 1, 3, device=self.device)
        self._desired_pos_w = torch.zeros(self.num_envs, 3, device=self.device)
        self._all_envs = torch.ones(self.num_envs, dtype=torch.bool, device=self.device)

        # Logging: episode sums per reward term; the last log lives on the device (no host reads in the step)
        self._episode_sums = torch.zeros(self.num_envs, len(REWARD_TERMS), device=self.device)
        self._log_names = [f"Episode_Reward/{k}" for k in REWARD_TERMS] + [
            "Episode_Termination/died",
            "Episode_Termination/time_out",
            "Metrics/final_distance_to_goal",
        ]
        self._log = torch.zeros(len(self._log_names), device=self.device)

        self._body_id = self._robot.find_bodies("body")[0]
        # on the device once: a captured step may not copy indices from the host
        self._body_ids = torch.tensor(self._body_id, dtype=torch.long, device=self.device)
        self._robot_mass = self._robot.data.default_mass[0].sum()
        self._gravity_magnitude = torch.tensor(self.sim.cfg.gravity, device=self.device).norm()
        self._robot_weight = (self._robot_mass * self._gravity_magnitude).item()

    def _setup_scene(self):
        self._robot = Articulation(self.cfg.robot)
        self.scene.articulations["robot"] = self._robot
        spawn_ground_plane(prim_path="/World/ground", cfg=self.cfg.terrain)
        light_cfg = sim_utils.DomeLightCfg(intensity=2000.0, color=(0.75, 0.75, 0.75))
        light_cfg.func("/World/Light", light_cfg)

    def step(self, action: torch.Tensor):
        obs, reward, terminated, truncated, extras = super().step(action)
        # A snapshot of the device-side log (Isaac Lab refreshes it in steps where some env finished).
        extras["log"].update(zip(self._log_names, self._log.clone().unbind()))
        return obs, reward, terminated, truncated, extras

    def _pre_physics_step(self, actions: torch.Tensor):
        self._actions = actions.clone().clamp(-1.0, 1.0)
        self._thrust[:, 0, 2] = self.cfg.thrust_to_weight * self._robot_weight * (self._actions[:, 0] + 1.0) / 2.0
        self._moment[:, 0, :] = self.cfg.moment_scale * self._actions[:, 1:]

    def _apply_action(self):
        # Body-frame wrench; device-side body ids and the all-envs mask keep the call free of host
        # copies and reads, so the step can be captured as a graph.
        self._robot.set_external_force_and_torque(
            self._thrust, self._moment, body_ids=self._body_ids, env_ids=self._all_envs
        )

    def _get_observations(self) -> dict:
        desired_pos_b, _ = subtract_frame_transforms(
            self._robot.data.root_pos_w, self._robot.data.root_quat_w, self._desired_pos_w
        )
        obs = torch.cat(
            [
                self._robot.data.root_lin_vel_b,
                self._robot.data.root_ang_vel_b,
                self._robot.data.projected_gravity_b,
                desired_pos_b,
            ],
            dim=-1,
        )
        return {"policy": obs}

    def _get_rewards(self) -> torch.Tensor:
        lin_vel = torch.sum(torch.square(self._robot.data.root_lin_vel_b), dim=1)
        ang_vel = torch.sum(torch.square(self._robot.data.root_ang_vel_b), dim=1)
        distance_to_goal = torch.linalg.norm(self._desired_pos_w - self._robot.data.root_pos_w, dim=1)
        distance_to_goal_mapped = 1 - torch.tanh(distance_to_goal / 0.8)
        rewards = torch.stack(
            [
                lin_vel * self.cfg.lin_vel_reward_scale * self.step_dt,
                ang_vel * self.cfg.ang_vel_reward_scale * self.step_dt,
                distance_to_goal_mapped * self.cfg.distance_to_goal_reward_scale * self.step_dt,
            ],
            dim=1,
        )
        self._episode_sums += rewards
        return rewards.sum(dim=1)

    def _get_dones(self) -> tuple[torch.Tensor, torch.Tensor]:
        time_out = self.episode_length_buf >= self.max_episode_length - 1
        height = self._robot.data.root_pos_w[:, 2]
        died = torch.logical_or(height < 0.1, height > 2.0)
        return died, time_out

    def _reset_mask(self, env_mask: torch.Tensor):
        self._log_finished_episodes(env_mask)
        super()._reset_mask(env_mask)
        # Spread out the resets when every env resets at once (avoids synchronised episodes in training)
        spread = torch.randint_like(self.episode_length_buf, high=int(self.max_episode_length))
        masked_copy_(self.episode_length_buf, env_mask.all().expand(self.num_envs), spread)

        masked_copy_(self._actions, env_mask, 0.0)
        # New goals, drawn for every env and kept where env_mask is set
        goal = torch.empty_like(self._desired_pos_w)
        goal[:, :2] = torch.empty_like(goal[:, :2]).uniform_(-2.0, 2.0) + self.scene.env_origins[:, :2]
        goal[:, 2] = torch.empty_like(goal[:, 2]).uniform_(0.5, 1.5)
        masked_copy_(self._desired_pos_w, env_mask, goal)
        # Robot state
        data = self._robot.data
        default_root_state = data.default_root_state.clone()
        default_root_state[:, :3] += self.scene.env_origins
        self._robot.write_root_pose_to_sim(default_root_state[:, :7], env_mask)
        self._robot.write_root_velocity_to_sim(default_root_state[:, 7:], env_mask)
        self._robot.write_joint_state_to_sim(data.default_joint_pos, data.default_joint_vel, None, env_mask)

    def _log_finished_episodes(self, env_mask: torch.Tensor) -> None:
        """Means over the envs in ``env_mask`` (Isaac Lab's log); kept as they were if the mask is empty."""
        finished = env_mask.float()
        count = finished.sum()
        mean_over = lambda x: (x * finished).sum() / count.clamp(min=1.0)  # noqa: E731
        final_distance = torch.linalg.norm(self._desired_pos_w - self._robot.data.root_pos_w, dim=1)
        log = torch.cat(
            [
                (self._episode_sums * finished[:, None]).sum(dim=0) / count.clamp(min=1.0) / self.max_episode_length_s,
                torch.stack(
                    [
                        (self.reset_terminated & env_mask).sum().float(),
                        (self.reset_time_outs & env_mask).sum().float(),
                        mean_over(final_distance),
                    ]
                ),
            ]
        )
        masked_copy_(self._log, (count > 0).expand(len(self._log_names)), log)
        masked_copy_(self._episode_sums, env_mask, 0.0)
