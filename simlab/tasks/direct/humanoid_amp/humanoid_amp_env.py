"""Humanoid AMP (Isaac Lab's ``HumanoidAmpEnv``): imitate a motion clip's style with adversarial motion priors.

The policy sets PD joint targets (``offset + scale * action`` spanning each joint's soft limits).
The observation of one frame is joint positions and velocities, the torso's height, its tangent and
normal (orientation), its linear and angular velocity, and the hands' and feet's positions relative
to the torso. skrl's ``AMP`` agent rewards the policy by a discriminator that tells the env's
frames (``extras["amp_obs"]``, the last ``num_amp_observations`` frames) from the clip's
(``collect_reference_motions``); the env's own reward is a constant 1 (the agent's task reward
weight is 0), or with ``imitation_reward`` a reward for the clip's poses and pace. Episodes start in
reference states of the clip (``reset_strategy``) and end when the torso drops below
``termination_height`` or after ``episode_length_s``.

Differences from Isaac Lab: the robot is simlab's 21-joint humanoid, with clips made for it; the
frames of an AMP observation are one env step apart in the env and in the reference motions
alike (Isaac Lab spaces reference frames by the clip's frame time); ``extras["amp_obs"]`` is the
transition's, taken before finished envs are reset (Isaac Lab's holds the reset state for them).
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import torch

import simlab.sim as sim_utils
from simlab.assets import Articulation
from simlab.envs import DirectRLEnv
from simlab.sim.spawners.from_files import spawn_ground_plane
from simlab.utils.env_mask import masked_copy_, rows
from simlab.utils.math import quat_apply

from .humanoid_amp_env_cfg import HumanoidAmpEnvCfg
from .motions.motion_loader import MotionLoader

RESET_STRATEGIES = ("default", "random", "random-start")


class HumanoidAmpEnv(DirectRLEnv):
    cfg: HumanoidAmpEnvCfg

    def __init__(self, cfg: HumanoidAmpEnvCfg, render_mode: str | None = None, **kwargs):
        if cfg.reset_strategy not in RESET_STRATEGIES:
            raise ValueError(f"Unknown reset_strategy '{cfg.reset_strategy}'. Allowed: {list(RESET_STRATEGIES)}.")
        super().__init__(cfg, render_mode, **kwargs)

        # action offset and scale: actions in [-0.5, 0.5] span the soft joint limits
        limits = self.robot.data.soft_joint_pos_limits[0]
        self.action_offset = 0.5 * (limits[:, 1] + limits[:, 0])
        self.action_scale = limits[:, 1] - limits[:, 0]

        self._motion_loader = MotionLoader(self.cfg.motion_file, device=self.device)

        # body and joint indices, in the robot and in the motion
        key_bodies = list(self.cfg.key_bodies)
        self.ref_body_index = self.robot.body_names.index(self.cfg.reference_body)
        self.key_body_indexes = [self.robot.body_names.index(name) for name in key_bodies]
        self.motion_dof_indexes = self._motion_loader.get_dof_index(self.robot.joint_names)
        self.motion_ref_body_index = self._motion_loader.get_body_index([self.cfg.reference_body])[0]
        self.motion_key_body_indexes = self._motion_loader.get_body_index(key_bodies)

        # the clip's poses (frames, joints) in the robot's joint order and its mean forward speed, for
        # the imitation reward and for judging a played policy (criterion.py)
        motion = self._motion_loader
        self.clip_joint_pos = motion.dof_positions[:, self.motion_dof_indexes]
        advance = (
            motion.body_positions[-1, self.motion_ref_body_index, 0]
            - motion.body_positions[0, self.motion_ref_body_index, 0]
        )
        self.clip_forward_speed = float(advance / motion.duration)

        # the AMP observation: the last num_amp_observations frames, newest first
        frames, size = self.cfg.num_amp_observations, self.cfg.amp_observation_space
        self.amp_observation_size = frames * size
        self.amp_observation_space = gym.spaces.Box(low=-np.inf, high=np.inf, shape=(self.amp_observation_size,))
        self.amp_observation_buffer = torch.zeros((self.num_envs, frames, size), device=self.device)
        # envs whose history restarts from their next frame (reset to the default pose)
        self._restart_history = torch.zeros(self.num_envs, dtype=torch.bool, device=self.device)
        # the transition's AMP observation, copied before finished envs are reset
        self._amp_obs = torch.zeros((self.num_envs, self.amp_observation_size), device=self.device)
        self.extras["amp_obs"] = self._amp_obs

    def _setup_scene(self):
        self.robot = Articulation(self.cfg.robot)
        spawn_ground_plane(prim_path="/World/ground", cfg=self.cfg.terrain)
        self.scene.articulations["robot"] = self.robot
        light_cfg = sim_utils.DomeLightCfg(intensity=2000.0, color=(0.75, 0.75, 0.75))
        light_cfg.func("/World/Light", light_cfg)

    def _pre_physics_step(self, actions: torch.Tensor):
        self.actions = actions.clone()

    def _apply_action(self):
        self.robot.set_joint_position_target(self.action_offset + self.action_scale * self.actions)

    def _frame(self) -> torch.Tensor:
        """This step's observation frame (num_envs, amp_observation_space)."""
        data = self.robot.data
        body_pos, body_quat = data.body_pos_w, data.body_quat_w
        return compute_obs(
            data.joint_pos,
            data.joint_vel,
            body_pos[:, self.ref_body_index],
            body_quat[:, self.ref_body_index],
            data.body_lin_vel_w[:, self.ref_body_index],
            data.body_ang_vel_w[:, self.ref_body_index],
            body_pos[:, self.key_body_indexes],
        )

    def _get_observations(self) -> dict:
        return {"policy": self._frame()}

    def _get_rewards(self) -> torch.Tensor:
        if not self.cfg.imitation_reward:
            return torch.ones((self.num_envs,), dtype=torch.float32, device=self.device)
        data = self.robot.data
        pose = torch.exp(-self.clip_pose_squared_error(data.joint_pos) / self.cfg.pose_sigma**2)
        speed_error = data.body_lin_vel_w[:, self.ref_body_index, 0] - self.clip_forward_speed
        return pose + torch.exp(-((speed_error / self.cfg.speed_sigma) ** 2))

    def clip_pose_squared_error(self, joint_pos: torch.Tensor) -> torch.Tensor:
        """Mean over joints of the squared error of ``joint_pos`` (N, joints) to the nearest clip frame:
        AMP imitates a style, not a clock, so a pose is compared with the clip's pose nearest to it."""
        poses = self.clip_joint_pos.to(joint_pos.device)
        return torch.cdist(joint_pos, poses).min(dim=1).values ** 2 / poses.shape[1]

    def _get_dones(self) -> tuple[torch.Tensor, torch.Tensor]:
        # the first hook after the physics steps, called once per step (observations are computed
        # twice: before and after the resets), so the AMP history advances here
        self._advance_amp_history()
        time_out = self.episode_length_buf >= self.max_episode_length - 1
        if self.cfg.early_termination:
            died = self.robot.data.body_pos_w[:, self.ref_body_index, 2] < self.cfg.termination_height
        else:
            died = torch.zeros_like(time_out)
        return died, time_out

    def _advance_amp_history(self) -> None:
        frame = self._frame()
        buffer = self.amp_observation_buffer
        shifted = torch.cat([frame.unsqueeze(1), buffer[:, :-1]], dim=1)
        restarted = frame.unsqueeze(1).expand_as(buffer)
        torch.where(rows(self._restart_history, buffer), restarted, shifted, out=buffer)
        self._restart_history.zero_()
        self._amp_obs.copy_(buffer.view(self.num_envs, -1))

    def _reset_mask(self, env_mask: torch.Tensor):
        super()._reset_mask(env_mask)
        if self.cfg.reset_strategy == "default":
            root_state, joint_pos, joint_vel = self._reset_strategy_default()
            masked_copy_(self._restart_history, env_mask, True)
        else:
            root_state, joint_pos, joint_vel = self._reset_strategy_random(env_mask, self.cfg.reset_strategy)
        self.robot.write_root_pose_to_sim(root_state[:, :7], env_mask)
        self.robot.write_root_velocity_to_sim(root_state[:, 7:], env_mask)
        self.robot.write_joint_state_to_sim(joint_pos, joint_vel, None, env_mask)

    # reset strategies: initial states for every env (written where the mask is set)

    def _reset_strategy_default(self) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        data = self.robot.data
        root_state = data.default_root_state.clone()
        root_state[:, :3] += self.scene.env_origins
        return root_state, data.default_joint_pos.clone(), data.default_joint_vel.clone()

    def _reset_strategy_random(
        self, env_mask: torch.Tensor, strategy: str
    ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """Reference state initialisation: the clip's pose at a random time (or at its start)."""
        n = self.num_envs
        if strategy == "random-start":
            times = torch.zeros(n, device=self.device)
        else:
            times = self._motion_loader.sample_times(n)
        dof_positions, dof_velocities, body_positions, body_rotations, body_lin_vel, body_ang_vel = (
            self._motion_loader.sample(num_samples=n, times=times)
        )
        root = self.motion_ref_body_index
        root_state = torch.cat(
            [
                body_positions[:, root] + self.scene.env_origins,
                body_rotations[:, root],
                body_lin_vel[:, root],
                body_ang_vel[:, root],
            ],
            dim=-1,
        )
        root_state[:, 2] += self.cfg.reference_lift
        # the history of these envs: the reference frames that led to the sampled time
        history = self.collect_reference_motions(n, times).view_as(self.amp_observation_buffer)
        masked_copy_(self.amp_observation_buffer, env_mask, history)
        masked_copy_(self._restart_history, env_mask, False)
        return root_state, dof_positions[:, self.motion_dof_indexes], dof_velocities[:, self.motion_dof_indexes]

    # env methods (called by skrl's AMP agent)

    def collect_reference_motions(
        self, num_samples: int, current_times: torch.Tensor | np.ndarray | None = None
    ) -> torch.Tensor:
        """AMP observations (num_samples, amp_observation_size) of the clip at ``current_times``
        (drawn uniformly when None): the frames at t, t - step_dt, ..., newest first."""
        if current_times is None:
            current_times = self._motion_loader.sample_times(num_samples)
        current_times = torch.as_tensor(current_times, dtype=torch.float32, device=self.device)
        offsets = self.step_dt * torch.arange(self.cfg.num_amp_observations, device=self.device)
        times = (current_times.unsqueeze(-1) - offsets).flatten()
        dof_positions, dof_velocities, body_positions, body_rotations, body_lin_vel, body_ang_vel = (
            self._motion_loader.sample(num_samples=times.numel(), times=times)
        )
        root = self.motion_ref_body_index
        frames = compute_obs(
            dof_positions[:, self.motion_dof_indexes],
            dof_velocities[:, self.motion_dof_indexes],
            body_positions[:, root],
            body_rotations[:, root],
            body_lin_vel[:, root],
            body_ang_vel[:, root],
            body_positions[:, self.motion_key_body_indexes],
        )
        return frames.view(-1, self.amp_observation_size)


def compute_obs(
    joint_pos: torch.Tensor,
    joint_vel: torch.Tensor,
    root_pos: torch.Tensor,
    root_quat: torch.Tensor,
    root_lin_vel: torch.Tensor,
    root_ang_vel: torch.Tensor,
    key_body_pos: torch.Tensor,
) -> torch.Tensor:
    """One observation frame (N, 2 D + 16 + 3 K) from joint states (N, D), the root body's pose and
    velocities (N, 3 / 4), and K key body positions (N, K, 3), all in the world frame.

    The root's orientation enters as its x and z axes (continuous, unlike a quaternion's sign); key
    bodies are relative to the root, so the frame does not depend on where the env is.
    """
    x_axis, z_axis = torch.zeros_like(root_pos), torch.zeros_like(root_pos)
    x_axis[:, 0] = 1.0
    z_axis[:, 2] = 1.0
    x_axis, z_axis = quat_apply(root_quat, x_axis), quat_apply(root_quat, z_axis)
    key_body_rel = (key_body_pos - root_pos.unsqueeze(-2)).flatten(start_dim=-2)
    return torch.cat(
        [joint_pos, joint_vel, root_pos[:, 2:3], x_axis, z_axis, root_lin_vel, root_ang_vel, key_body_rel], dim=-1
    )
