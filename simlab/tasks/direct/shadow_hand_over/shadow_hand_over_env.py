"""Two Shadow Hands pass a ball, direct multi-agent workflow (Isaac Lab's ``direct/shadow_hand_over``).

Agents "right_hand" and "left_hand" each drive one hand (20 joint position targets in [-1, 1] spread
over the joints' ranges). Each observes its own hand (joint positions scaled to [-1, 1] and
velocities, fingertip positions, orientations and velocities, its last actions), the ball (position,
orientation, velocities) and the goal (position, orientation, the rotation between ball and goal):
157 values. The shared state holds both hands, the ball and the goal: 290 values. Both agents earn
``2 exp(-dist_reward_scale * |ball - goal|)``; an episode ends when the ball drops below ``fall_dist``.

Differences from Isaac Lab's file, none visible to a policy: resets select envs by a mask (the step
has fixed shapes and replays as one CUDA graph); a reset puts a coupled distal joint where its middle
joint is; the goal marker is placed when an image is rendered; each env records whether its last
finished episode caught the ball (``episode_caught``: the ball came within ``catch_radius`` of the
goal and did not fall) for ``simlab bench solve``.
"""

from __future__ import annotations

import torch

import simlab.sim as sim_utils
from simlab.assets import Articulation, RigidObject
from simlab.envs import DirectMARLEnv
from simlab.markers import VisualizationMarkers
from simlab.sim.spawners.from_files import GroundPlaneCfg, spawn_ground_plane
from simlab.tasks.direct.inhand_manipulation.inhand_manipulation_env import randomize_rotation, scale, unscale
from simlab.utils.env_mask import masked_copy_
from simlab.utils.math import quat_conjugate, quat_mul, sample_uniform, saturate

from .shadow_hand_over_env_cfg import ShadowHandOverEnvCfg


class ShadowHandOverEnv(DirectMARLEnv):
    cfg: ShadowHandOverEnvCfg

    def __init__(self, cfg: ShadowHandOverEnvCfg, render_mode: str | None = None, **kwargs):
        super().__init__(cfg, render_mode, **kwargs)
        n, device = self.num_envs, self.device
        self.hands = {"right_hand": self.right_hand, "left_hand": self.left_hand}
        self.num_hand_dofs = self.right_hand.num_joints
        joint_names = self.right_hand.joint_names  # the two hands are the same model
        self.actuated_dof_indices = sorted(joint_names.index(name) for name in cfg.actuated_joint_names)
        self._actuated = torch.tensor(self.actuated_dof_indices, device=device)
        self._followers = torch.tensor(
            [joint_names.index(j) for j in cfg.coupled_joints], dtype=torch.long, device=device
        )
        self._leaders = torch.tensor(
            [joint_names.index(j) for j in cfg.coupled_joints.values()], dtype=torch.long, device=device
        )
        finger_bodies = sorted(self.right_hand.body_names.index(name) for name in cfg.fingertip_body_names)
        self.num_fingertips = len(finger_bodies)
        self._tips = torch.tensor(finger_bodies, device=device)

        limits = self.right_hand.data.joint_pos_limits.to(device)
        self.hand_dof_lower_limits, self.hand_dof_upper_limits = limits[..., 0], limits[..., 1]
        # the last applied position targets of each hand
        self.prev_targets = {agent: torch.zeros((n, self.num_hand_dofs), device=device) for agent in self.hands}

        self.goal_rot = torch.zeros((n, 4), device=device)
        self.goal_rot[:, 0] = 1.0
        self.goal_pos = torch.tensor(cfg.goal_pos, device=device).repeat((n, 1))
        self.goal_markers = VisualizationMarkers(cfg.goal_object_cfg)
        self.sim.add_render_callback(self._place_goal_markers)

        self.reached = torch.zeros(n, dtype=torch.bool, device=device)
        """Whether the ball has come within ``catch_radius`` of the goal in this episode."""
        self.episode_caught = torch.zeros(n, dtype=torch.bool, device=device)
        """Whether each env's last finished episode caught the ball (reached the goal, did not fall)."""
        self.x_unit_tensor = torch.tensor([1.0, 0.0, 0.0], device=device).repeat((n, 1))
        self.y_unit_tensor = torch.tensor([0.0, 1.0, 0.0], device=device).repeat((n, 1))
        self.actions = {agent: torch.zeros((n, 20), device=device) for agent in self.hands}
        self._compute_intermediate_values()

    def _setup_scene(self):
        self.right_hand = Articulation(self.cfg.right_robot_cfg)
        self.left_hand = Articulation(self.cfg.left_robot_cfg)
        self.object = RigidObject(self.cfg.object_cfg)
        spawn_ground_plane(prim_path="/World/ground", cfg=GroundPlaneCfg())
        self.scene.clone_environments(copy_from_source=False)
        self.scene.articulations["right_robot"] = self.right_hand
        self.scene.articulations["left_robot"] = self.left_hand
        self.scene.rigid_objects["object"] = self.object
        light_cfg = sim_utils.DomeLightCfg(intensity=2000.0, color=(0.75, 0.75, 0.75))
        light_cfg.func("/World/Light", light_cfg)

    # actions

    def _pre_physics_step(self, actions: dict[str, torch.Tensor]) -> None:
        self.actions = actions

    def _apply_action(self) -> None:
        act = self._actuated
        lower, upper = self.hand_dof_lower_limits[:, act], self.hand_dof_upper_limits[:, act]
        alpha = self.cfg.act_moving_average
        for agent, hand in self.hands.items():
            targets = (
                alpha * scale(self.actions[agent], lower, upper) + (1.0 - alpha) * self.prev_targets[agent][:, act]
            )
            targets = saturate(targets, lower, upper)
            self.prev_targets[agent][:, act] = targets
            hand.set_joint_position_target(targets, joint_ids=act)

    # observations, rewards, dones

    def _hand_observations(self, agent: str) -> torch.Tensor:
        hand, n, tips = self.hand_state[agent], self.num_envs, self.num_fingertips
        return torch.cat(
            (
                unscale(hand["dof_pos"], self.hand_dof_lower_limits, self.hand_dof_upper_limits),
                self.cfg.vel_obs_scale * hand["dof_vel"],
                hand["fingertip_pos"].reshape(n, tips * 3),
                hand["fingertip_rot"].reshape(n, tips * 4),
                hand["fingertip_vel"].reshape(n, tips * 6),
                self.actions[agent],
            ),
            dim=-1,
        )

    def _object_and_goal(self) -> torch.Tensor:
        return torch.cat(
            (
                self.object_pos,
                self.object_rot,
                self.object_linvel,
                self.cfg.vel_obs_scale * self.object_angvel,
                self.goal_pos,
                self.goal_rot,
                quat_mul(self.object_rot, quat_conjugate(self.goal_rot)),
            ),
            dim=-1,
        )

    def _get_observations(self) -> dict[str, torch.Tensor]:
        shared = self._object_and_goal()
        return {agent: torch.cat((self._hand_observations(agent), shared), dim=-1) for agent in self.hands}

    def _get_states(self) -> torch.Tensor:
        hands = [self._hand_observations(agent) for agent in self.hands]
        return torch.cat((*hands, self._object_and_goal()), dim=-1)

    def _get_rewards(self) -> dict[str, torch.Tensor]:
        goal_dist = torch.norm(self.object_pos - self.goal_pos, p=2, dim=-1)
        rew_dist = 2 * torch.exp(-self.cfg.dist_reward_scale * goal_dist)
        self.reached |= goal_dist <= self.cfg.catch_radius
        log = self.extras.setdefault("log", {})
        log["dist_reward"] = rew_dist.mean()
        log["dist_goal"] = goal_dist.mean()
        return {"right_hand": rew_dist, "left_hand": rew_dist}

    def _get_dones(self) -> tuple[dict[str, torch.Tensor], dict[str, torch.Tensor]]:
        self._compute_intermediate_values()
        out_of_reach = self.object_pos[:, 2] <= self.cfg.fall_dist
        time_out = self.episode_length_buf >= self.max_episode_length - 1
        return (
            {agent: out_of_reach for agent in self.cfg.possible_agents},
            {agent: time_out for agent in self.cfg.possible_agents},
        )

    # resets

    def _reset_mask(self, env_mask: torch.Tensor) -> None:
        # the episode that ends: caught if the ball reached the goal and is still up
        masked_copy_(self.episode_caught, env_mask, self.reached & (self.object_pos[:, 2] > self.cfg.fall_dist))
        self.reached.masked_fill_(env_mask, False)
        super()._reset_mask(env_mask)
        n, device = self.num_envs, self.device

        rand = sample_uniform(-1.0, 1.0, (n, 2), device=device)
        masked_copy_(
            self.goal_rot, env_mask, randomize_rotation(rand[:, 0], rand[:, 1], self.x_unit_tensor, self.y_unit_tensor)
        )

        # ball: its default pose shifted by up to reset_position_noise, a random orientation, at rest
        state = self.object.data.default_root_state.clone()
        pos_noise = sample_uniform(-1.0, 1.0, (n, 3), device=device)
        state[:, 0:3] += self.cfg.reset_position_noise * pos_noise + self.scene.env_origins
        rot_noise = sample_uniform(-1.0, 1.0, (n, 2), device=device)
        state[:, 3:7] = randomize_rotation(rot_noise[:, 0], rot_noise[:, 1], self.x_unit_tensor, self.y_unit_tensor)
        state[:, 7:] = 0.0
        self.object.write_root_pose_to_sim(state[:, :7], env_mask)
        self.object.write_root_velocity_to_sim(state[:, 7:], env_mask)

        # each hand: the default pose moved towards a random point of each joint's range
        for agent, hand in self.hands.items():
            default_pos = hand.data.default_joint_pos
            delta_max = self.hand_dof_upper_limits - default_pos
            delta_min = self.hand_dof_lower_limits - default_pos
            dof_pos_noise = sample_uniform(-1.0, 1.0, (n, self.num_hand_dofs), device=device)
            dof_pos = default_pos + self.cfg.reset_dof_pos_noise * (
                delta_min + (delta_max - delta_min) * 0.5 * dof_pos_noise
            )
            dof_vel_noise = sample_uniform(-1.0, 1.0, (n, self.num_hand_dofs), device=device)
            dof_vel = hand.data.default_joint_vel + self.cfg.reset_dof_vel_noise * dof_vel_noise
            if len(self._followers):
                dof_pos[:, self._followers] = dof_pos[:, self._leaders]
                dof_vel[:, self._followers] = dof_vel[:, self._leaders]
            masked_copy_(self.prev_targets[agent], env_mask, dof_pos)
            hand.set_joint_position_target(dof_pos, env_ids=env_mask)
            hand.write_joint_state_to_sim(dof_pos, dof_vel, env_ids=env_mask)
        self._compute_intermediate_values()

    def _place_goal_markers(self) -> None:
        """The goal ball above the left palm, drawn in rendered images (called before each one)."""
        self.goal_markers.visualize(self.goal_pos + self.scene.env_origins, self.goal_rot)

    # helpers

    def _compute_intermediate_values(self) -> None:
        origins = self.scene.env_origins
        self.hand_state = {}
        for agent, hand in self.hands.items():
            data = hand.data
            self.hand_state[agent] = {
                "fingertip_pos": data.body_pos_w[:, self._tips] - origins.unsqueeze(1),
                "fingertip_rot": data.body_quat_w[:, self._tips],
                "fingertip_vel": data.body_vel_w[:, self._tips],
                "dof_pos": data.joint_pos,
                "dof_vel": data.joint_vel,
            }
        ball = self.object.data
        self.object_pos = ball.root_pos_w - origins
        self.object_rot = ball.root_quat_w
        self.object_linvel = ball.root_lin_vel_w
        self.object_angvel = ball.root_ang_vel_w
