"""In-hand reorientation, direct workflow (Isaac Lab's ``direct/inhand_manipulation``): turn a cube in a
palm-up hand until it matches a goal orientation, then the next one.

The env serves every hand whose config names its ``actuated_joint_names`` and ``fingertip_body_names``
(``simlab.tasks.direct.allegro_hand``, ``shadow_hand``). Actions in [-1, 1] are joint position targets
spread over each actuated joint's range, smoothed by ``act_moving_average``. Observations
(``obs_type``): "full" (joint positions scaled to [-1, 1] and velocities; the cube's position,
orientation and velocities; the in-hand position, goal orientation and the rotation between them;
fingertip positions, orientations and velocities; the last actions) or "openai" (fingertip positions,
the cube's position, the rotation to the goal, the last actions: OpenAI's table 2). With
``asymmetric_obs`` the critic gets the full observations and the fingertips' force-torque readings
(``"critic"``, ``state_space`` long).

Reward (Isaac Lab's terms): ``dist_reward_scale`` times the cube's distance from the in-hand position,
``rot_reward_scale / (|rotation to the goal| + rot_eps)``, ``action_penalty_scale`` times the squared
actions, ``reach_goal_bonus`` when the rotation is within ``success_tolerance`` (the goal is then
redrawn at once and the env's success count grows), ``fall_penalty`` when the cube is ``fall_dist`` from
the in-hand position, which also ends the episode. ``consecutive_successes``, the running mean
(``av_factor``) of the success counts of the episodes that end, is logged as Isaac Lab logs it.

Differences from Isaac Lab's file, none visible to a policy: resets and goal redraws select envs by a
mask (draws made for every env, kept where it is set), so the step has fixed shapes and replays as one
CUDA graph; the goal marker is placed when an image is rendered, not in the step; the count of goals
reached in each episode that ended is kept per env (``episode_successes``) for ``simlab bench solve``.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from typing import TYPE_CHECKING

import torch

import simlab.sim as sim_utils
from simlab.assets import Articulation, RigidObject
from simlab.envs import DirectRLEnv
from simlab.markers import VisualizationMarkers
from simlab.sim.spawners.from_files import GroundPlaneCfg, spawn_ground_plane
from simlab.utils.env_mask import masked_copy_
from simlab.utils.math import quat_from_angle_axis, quat_mul, sample_uniform

if TYPE_CHECKING:
    from simlab.tasks.direct.allegro_hand.allegro_hand_env_cfg import AllegroHandEnvCfg

GOAL_MARKER_POS = (-0.2, -0.45, 0.68)
"""Where the goal cube is drawn, in each env's frame (beside the hand)."""


COMPUTED_WHEN_READ: list[str] = []
"""The env's observation quantities made by :func:`computed_when_read`."""


def computed_when_read(compute: Callable[[InHandManipulationEnv], torch.Tensor]) -> property:
    """An attribute of Isaac Lab's env computed when read instead of kept: a tensor bound anew in each
    step would cost a copy per replay of the CUDA graph (``simlab.envs.utils.tensor_slots``). A value code
    assigns to it (Isaac Lab-style code that edits an observation) is what it reads until the next state
    (``_compute_intermediate_values``)."""
    name = compute.__name__
    COMPUTED_WHEN_READ.append(name)

    def get(env: InHandManipulationEnv) -> torch.Tensor:
        assigned = env.__dict__.get(name)
        return compute(env) if assigned is None else assigned

    def assign(env: InHandManipulationEnv, value: torch.Tensor) -> None:
        env.__dict__[name] = value

    return property(get, assign, doc=compute.__doc__)


class InHandManipulationEnv(DirectRLEnv):
    cfg: AllegroHandEnvCfg

    def __init__(self, cfg: AllegroHandEnvCfg, render_mode: str | None = None, **kwargs):
        super().__init__(cfg, render_mode, **kwargs)
        n, device = self.num_envs, self.device
        self.num_hand_dofs = self.hand.num_joints

        # position targets: the last applied (prev) and the current ones
        self.hand_dof_targets = torch.zeros((n, self.num_hand_dofs), device=device)
        self.prev_targets = torch.zeros((n, self.num_hand_dofs), device=device)
        self.cur_targets = torch.zeros((n, self.num_hand_dofs), device=device)

        # actuated joints and fingertips in the model's order (Isaac Lab sorts the ids the same way)
        self.actuated_dof_indices = sorted(self.hand.joint_names.index(name) for name in cfg.actuated_joint_names)
        # every joint actuated (the Allegro Hand): a slice, so that the targets are written without a gather
        all_joints = self.actuated_dof_indices == list(range(self.num_hand_dofs))
        self._actuated = slice(None) if all_joints else torch.tensor(self.actuated_dof_indices, device=device)
        self.finger_bodies = sorted(self.hand.body_names.index(name) for name in cfg.fingertip_body_names)
        # joints the model couples to another (follower: leader): a reset puts them where they belong
        coupled = getattr(cfg, "coupled_joints", {})  # simlab's field; Isaac Lab's configs have none
        follower_ids = [self.hand.joint_names.index(name) for name in coupled]
        leader_ids = [self.hand.joint_names.index(name) for name in coupled.values()]
        self._followers = torch.tensor(follower_ids, dtype=torch.long, device=device)
        self._leaders = torch.tensor(leader_ids, dtype=torch.long, device=device)
        self.num_fingertips = len(self.finger_bodies)
        # index tensors made once on the step's device (a Python list index is copied from the host each use)
        self._tips = torch.tensor(self.finger_bodies, device=device)

        limits = self.hand.data.joint_pos_limits.to(device)
        self.hand_dof_lower_limits = limits[..., 0]
        self.hand_dof_upper_limits = limits[..., 1]

        self.reset_goal_buf = torch.zeros(n, dtype=torch.bool, device=device)
        # where the cube belongs: 4 cm below its spawn point (env frame)
        self.in_hand_pos = self.object.data.default_root_state[:, 0:3].clone()
        self.in_hand_pos[:, 2] -= 0.04
        self.goal_rot = torch.zeros((n, 4), device=device)
        self.goal_rot[:, 0] = 1.0
        self.goal_pos = torch.tensor(GOAL_MARKER_POS, device=device).repeat((n, 1))
        self.goal_markers = VisualizationMarkers(self.cfg.goal_object_cfg)
        self.sim.add_render_callback(self._place_goal_markers)

        self._zero_velocities = torch.zeros((n, 6), device=device)  # the cube's at a reset
        # what the step computes, written in place: a tensor bound anew in each step would cost a copy per
        # replay of the CUDA graph (simlab.envs.utils.tensor_slots)
        self._action_targets = torch.zeros((n, len(self.actuated_dof_indices)), device=device)
        self._goal_dist = torch.zeros(n, device=device)
        self._rot_dist = torch.zeros(n, device=device)
        self._fell = torch.zeros(n, dtype=torch.bool, device=device)
        self.successes = torch.zeros(n, device=device)
        self.episode_successes = torch.zeros(n, device=device)
        """Goals reached in each env's last finished episode."""
        self.consecutive_successes = torch.zeros(1, device=device)

        self._compute_intermediate_values()

    def _setup_scene(self):
        self.hand = Articulation(self.cfg.robot_cfg)
        self.object = RigidObject(self.cfg.object_cfg)
        spawn_ground_plane(prim_path="/World/ground", cfg=GroundPlaneCfg())
        self.scene.clone_environments(copy_from_source=False)
        self.scene.articulations["robot"] = self.hand
        self.scene.rigid_objects["object"] = self.object
        if self.cfg.asymmetric_obs:  # the critic reads the fingertips' incoming joint wrenches (cfrc_int)
            sim_utils.compute_body_interaction_forces(self.sim.spec)
        light_cfg = sim_utils.DomeLightCfg(intensity=2000.0, color=(0.75, 0.75, 0.75))
        light_cfg.func("/World/Light", light_cfg)

    def step(self, action: torch.Tensor):
        obs, reward, terminated, truncated, extras = super().step(action)
        extras["log"]["consecutive_successes"] = self.consecutive_successes.mean()
        return obs, reward, terminated, truncated, extras

    # actions

    def _pre_physics_step(self, actions: torch.Tensor) -> None:
        self.actions.copy_(actions)
        # the actions' targets over the joint ranges, the same for each of the step's physics steps (the
        # limits are read each step: randomization events may change them)
        act = self._actuated
        lower, upper = self.hand_dof_lower_limits[:, act], self.hand_dof_upper_limits[:, act]
        scale(self.actions, lower, upper, out=self._action_targets)
        if self.cfg.act_moving_average == 1.0:  # no smoothing: the targets are final, set them once
            self._set_targets(self._action_targets, lower, upper)

    def _apply_action(self) -> None:
        alpha = self.cfg.act_moving_average
        if alpha == 1.0:  # set once in _pre_physics_step
            return
        # the moving average advances each physics step, as Isaac Lab's
        act = self._actuated
        lower, upper = self.hand_dof_lower_limits[:, act], self.hand_dof_upper_limits[:, act]
        self._set_targets(alpha * self._action_targets + (1.0 - alpha) * self.prev_targets[:, act], lower, upper)

    def _set_targets(self, targets: torch.Tensor, lower: torch.Tensor, upper: torch.Tensor) -> None:
        act = self._actuated
        if isinstance(act, slice):  # every joint: clamped into cur_targets itself
            targets = torch.clamp(targets, lower, upper, out=self.cur_targets)
        else:
            targets = torch.clamp(targets, lower, upper)  # Isaac Lab's saturate, in one kernel
            self.cur_targets[:, act] = targets
        self.prev_targets[:, act] = targets
        self.hand.set_joint_position_target(targets, joint_ids=act)

    # observations, rewards, dones

    def _get_observations(self) -> dict:
        self._compute_intermediate_values()
        if self.cfg.obs_type == "openai":
            obs = self.compute_reduced_observations()
        elif self.cfg.obs_type == "full":
            obs = self.compute_full_observations()
        else:
            raise ValueError(f"obs_type must be 'openai' or 'full', got '{self.cfg.obs_type}'")
        if self.cfg.asymmetric_obs:
            self.fingertip_force_sensors = self.hand.data.body_incoming_joint_wrench_b[:, self._tips]
            return {"policy": obs, "critic": self.compute_full_state()}
        return {"policy": obs}

    def _get_rewards(self) -> torch.Tensor:
        """:func:`compute_rewards` for the env's state, with the env's counters updated in place and the
        distances the dones computed for this state reused."""
        cfg = self.cfg
        if cfg.max_consecutive_success <= 0:  # else the dones computed it
            rotation_distance(self.object_rot, self.goal_rot, out=self._rot_dist)
        rot_dist = self._rot_dist
        reward = self._goal_dist * cfg.dist_reward_scale
        rot_reward = torch.add(rot_dist, cfg.rot_eps).reciprocal_()
        if cfg.rot_reward_scale != 1.0:  # a product by 1 changes nothing
            rot_reward.mul_(cfg.rot_reward_scale)
        reward.add_(rot_reward)
        reward.add_(torch.sum(self.actions**2, dim=-1), alpha=cfg.action_penalty_scale)
        # a reached goal (or one flagged for a redraw) pays the bonus and counts
        self.reset_goal_buf |= rot_dist <= cfg.success_tolerance
        reached = self.reset_goal_buf.float()
        self.successes.add_(reached)
        reward.add_(reached, alpha=cfg.reach_goal_bonus)
        if cfg.fall_penalty != 0:
            reward.add_(self._fell.float(), alpha=cfg.fall_penalty)
        update_consecutive_successes(
            self.consecutive_successes, self.successes, (self._fell | self.reset_buf).float(), cfg.av_factor
        )
        # a reached goal is replaced by a new one at once
        self._reset_target_pose(self.reset_goal_buf)
        return reward

    def _get_dones(self) -> tuple[torch.Tensor, torch.Tensor]:
        self._compute_object_pose()
        # the cube fell: too far from where it belongs in the hand (the reward reads both again)
        torch.linalg.vector_norm(self.object_pos - self.in_hand_pos, dim=-1, out=self._goal_dist)
        out_of_reach = torch.ge(self._goal_dist, self.cfg.fall_dist, out=self._fell)
        time_out = self.episode_length_buf >= self.max_episode_length - 1
        if self.cfg.max_consecutive_success > 0:
            # a goal within tolerance restarts the episode clock; enough successes end the episode
            rotation_distance(self.object_rot, self.goal_rot, out=self._rot_dist)
            self.episode_length_buf.masked_fill_(self._rot_dist <= self.cfg.success_tolerance, 0)
            time_out = time_out | (self.successes >= self.cfg.max_consecutive_success)
        return out_of_reach, time_out

    # resets

    def _reset_mask(self, env_mask: torch.Tensor) -> None:
        super()._reset_mask(env_mask)
        n, device = self.num_envs, self.device
        self._reset_target_pose(env_mask)

        # cube: its default pose shifted by up to reset_position_noise, a random orientation, at rest
        # (the draws in Isaac Lab's order, so that a seed gives its episodes); written in the env's frame,
        # the orientation as drawn (a unit quaternion)
        pos_noise = sample_uniform(-1.0, 1.0, (n, 3), device=device)
        pos = self.object.data.default_root_state[:, 0:3] + (
            self.cfg.reset_position_noise * pos_noise + self.scene.env_origins
        )
        rot = random_orientation(sample_uniform(-1.0, 1.0, (n, 2), device=device))
        self.object.write_root_pose_to_sim(torch.cat((pos, rot), dim=-1), env_mask)
        # at rest: zero in any frame, so written as MuJoCo holds it (the angular part in the cube's frame)
        # without turning it from the world frame
        zero = self._zero_velocities
        self.object.write_root_ang_vel_b_to_sim(zero[:, 3:6], env_mask, lin_vel_w=zero[:, 0:3])

        # hand: the default pose moved towards a random point of each joint's range (the limits are read
        # here: randomization events may change them)
        default_pos = self.hand.data.default_joint_pos
        delta_max = self.hand_dof_upper_limits - default_pos
        delta_min = self.hand_dof_lower_limits - default_pos
        dof_pos_noise = sample_uniform(-1.0, 1.0, (n, self.num_hand_dofs), device=device)
        # Isaac Lab's delta_min + (delta_max - delta_min) * 0.5 * noise, to the bit (0.5 t is exact)
        rand_delta = torch.add(delta_min, (delta_max - delta_min) * dof_pos_noise, alpha=0.5)
        dof_pos = default_pos + self.cfg.reset_dof_pos_noise * rand_delta
        dof_vel_noise = sample_uniform(-1.0, 1.0, (n, self.num_hand_dofs), device=device)  # drawn even if unused
        dof_vel = self.hand.data.default_joint_vel
        if self.cfg.reset_dof_vel_noise != 0.0:
            dof_vel = dof_vel + self.cfg.reset_dof_vel_noise * dof_vel_noise
        if len(self._followers):
            dof_vel = dof_vel.clone()
            dof_pos[:, self._followers] = dof_pos[:, self._leaders]
            dof_vel[:, self._followers] = dof_vel[:, self._leaders]
        for buffer in (self.prev_targets, self.cur_targets, self.hand_dof_targets):
            masked_copy_(buffer, env_mask, dof_pos)
        self.hand.set_joint_position_target(dof_pos, env_ids=env_mask)
        self.hand.write_joint_state_to_sim(dof_pos, dof_vel, env_ids=env_mask)

        masked_copy_(self.episode_successes, env_mask, self.successes)
        self.successes.masked_fill_(env_mask, 0.0)
        # the observations that follow read the new state (_compute_intermediate_values)

    def _reset_target_pose(self, env_mask: torch.Tensor) -> None:
        """A new random goal orientation where ``env_mask`` is set."""
        rand = sample_uniform(-1.0, 1.0, (self.num_envs, 2), device=self.device)
        masked_copy_(self.goal_rot, env_mask, random_orientation(rand))
        self.reset_goal_buf.masked_fill_(env_mask, False)

    def _place_goal_markers(self) -> None:
        """The goal cube beside the hand, drawn in rendered images (called before each one)."""
        self.goal_markers.visualize(self.goal_pos + self.scene.env_origins, self.goal_rot)

    # helpers

    def _compute_object_pose(self) -> None:
        """The cube's pose in the env's frame: what the dones and rewards read (no forward pass; views of
        the cube's joint state, exact in the env's frame)."""
        self.object_pos = self.object.data.root_pos_env
        self.object_rot = self.object.data.root_quat_w

    def _compute_intermediate_values(self) -> None:
        """The cube's pose; the rest of what the observations read is computed when read (the properties
        below), once per step: nothing is kept that a CUDA graph's replay would have to copy."""
        self._compute_object_pose()
        for name in COMPUTED_WHEN_READ:  # what code assigned to them since the last state
            self.__dict__.pop(name, None)

    # what the observations read (Isaac Lab's env keeps these as attributes); the fingertips' poses and
    # velocities are derived quantities: reading them runs the step's one kinematics pass (after the resets)

    @computed_when_read
    def fingertip_pos(self) -> torch.Tensor:
        """(num_envs, fingertips, 3) in the env's frame."""
        return self.hand.data.body_pos_env[:, self._tips]

    @computed_when_read
    def fingertip_rot(self) -> torch.Tensor:
        return self.hand.data.body_quat_w[:, self._tips]

    @computed_when_read
    def fingertip_velocities(self) -> torch.Tensor:
        return self.hand.data.body_vel_w[:, self._tips]

    @computed_when_read
    def hand_dof_pos(self) -> torch.Tensor:
        return self.hand.data.joint_pos

    @computed_when_read
    def hand_dof_vel(self) -> torch.Tensor:
        return self.hand.data.joint_vel

    @computed_when_read
    def object_linvel(self) -> torch.Tensor:
        return self.object.data.root_lin_vel_w

    @computed_when_read
    def object_angvel(self) -> torch.Tensor:
        return self.object.data.root_ang_vel_w

    @property
    def object_velocities(self) -> torch.Tensor:
        """The cube's linear and angular velocity (world frame), as Isaac Lab's env keeps it."""
        return torch.cat((self.object_linvel, self.object_angvel), dim=-1)

    def compute_reduced_observations(self) -> torch.Tensor:
        """OpenAI's observations (arXiv:1808.00177, table 2): fingertips, cube position, rotation to the goal."""
        return torch.cat([term for _, term in self._reduced_observation_terms()], dim=-1)

    def compute_full_observations(self) -> torch.Tensor:
        return torch.cat([term for _, term in self._full_observation_terms()], dim=-1)

    def _reduced_observation_terms(self) -> list[tuple[str, torch.Tensor]]:
        return [
            ("fingertip_pos", self.fingertip_pos.reshape(self.num_envs, self.num_fingertips * 3)),
            ("object_pos", self.object_pos),
            ("rotation_to_goal", quat_mul_conjugate(self.object_rot, self.goal_rot)),
            ("actions", self.actions),
        ]

    def _full_observation_terms(self) -> list[tuple[str, torch.Tensor]]:
        n, tips = self.num_envs, self.num_fingertips
        return [
            ("hand_dof_pos", unscale(self.hand_dof_pos, self.hand_dof_lower_limits, self.hand_dof_upper_limits)),
            ("hand_dof_vel", self.cfg.vel_obs_scale * self.hand_dof_vel),
            ("object_pos", self.object_pos),
            ("object_rot", self.object_rot),
            ("object_linvel", self.object_linvel),
            ("object_angvel", self.cfg.vel_obs_scale * self.object_angvel),
            ("in_hand_pos", self.in_hand_pos),
            ("goal_rot", self.goal_rot),
            ("rotation_to_goal", quat_mul_conjugate(self.object_rot, self.goal_rot)),
            ("fingertip_pos", self.fingertip_pos.reshape(n, tips * 3)),
            ("fingertip_rot", self.fingertip_rot.reshape(n, tips * 4)),
            ("fingertip_velocities", self.fingertip_velocities.reshape(n, tips * 6)),
            ("actions", self.actions),
        ]

    def observation_columns(self, group: str) -> list[tuple[str, int]] | None:
        """The policy observation's terms and widths, in order: what the step's non-finite-output error
        names columns by (only read on that error path)."""
        if group != "policy":
            return None
        terms = self._reduced_observation_terms() if self.cfg.obs_type == "openai" else self._full_observation_terms()
        return [(name, term.shape[-1]) for name, term in terms]

    def compute_full_state(self) -> torch.Tensor:
        """The critic's observation: the full observations and the fingertips' force-torque readings
        (the wrench each fingertip receives through its joint, in its own frame), before the actions."""
        full = self.compute_full_observations()
        wrenches = self.cfg.force_torque_obs_scale * self.fingertip_force_sensors.reshape(self.num_envs, -1)
        num_actions = self.actions.shape[-1]
        return torch.cat((full[:, :-num_actions], wrenches, self.actions), dim=-1)


def scale(x: torch.Tensor, lower: torch.Tensor, upper: torch.Tensor, out: torch.Tensor | None = None) -> torch.Tensor:
    """[-1, 1] onto [lower, upper]: ``0.5 (x + 1) (upper - lower) + lower`` (into ``out`` if given)."""
    # 0.5 t is exact (a power of two): adding 0.5 (x + 1)(upper - lower) with alpha rounds as Isaac Lab's
    return torch.add(lower, (x + 1.0) * (upper - lower), alpha=0.5, out=out)


def unscale(x: torch.Tensor, lower: torch.Tensor, upper: torch.Tensor) -> torch.Tensor:
    """[lower, upper] onto [-1, 1]: Isaac Lab's ``(2 x - upper - lower) / (upper - lower)`` as
    ``2 (x - lower) / (upper - lower) - 1`` (three kernels instead of five)."""
    return torch.addcdiv(_minus_one(x.device, x.dtype), x - lower, upper - lower, value=2.0)


@functools.lru_cache(maxsize=16)
def _minus_one(device: torch.device, dtype: torch.dtype) -> torch.Tensor:
    """Made once per device (a step captured as a CUDA graph may not copy from the host)."""
    return torch.tensor(-1.0, dtype=dtype, device=device)


def randomize_rotation(
    rand0: torch.Tensor, rand1: torch.Tensor, x_unit: torch.Tensor, y_unit: torch.Tensor
) -> torch.Tensor:
    """A rotation about x by ``rand0 * pi`` followed by one about y by ``rand1 * pi`` (rand in [-1, 1])."""
    return quat_mul(quat_from_angle_axis(rand0 * math.pi, x_unit), quat_from_angle_axis(rand1 * math.pi, y_unit))


def random_orientation(rand: torch.Tensor) -> torch.Tensor:
    """``randomize_rotation`` about x by ``rand[:, 0] * pi`` and y by ``rand[:, 1] * pi``, folded: the product
    of (c0, s0, 0, 0) and (c1, 0, s1, 0) is (c0 c1, s0 c1, c0 s1, s0 s1) (half-angle cosines and sines),
    five kernels instead of some thirty."""
    half = rand * (math.pi / 2)
    cos_sin = torch.empty((*half.shape[:-1], 2, 2), dtype=half.dtype, device=half.device)  # (n, [cos, sin], [x, y])
    torch.cos(half, out=cos_sin[:, 0])
    torch.sin(half, out=cos_sin[:, 1])
    # (cos, sin) of y times (cos, sin) of x: rows (c1 c0, c1 s0), (s1 c0, s1 s0) = (w, x), (y, z)
    return (cos_sin[:, :, 1].unsqueeze(-1) * cos_sin[:, :, 0].unsqueeze(-2)).reshape(-1, 4)


# q1 * conj(q2) = sum_j sign[i, j] q1[index[i, j]] q2[j]: quat_mul's tables with the conjugate's signs folded in
_DIFF_INDEX = ((0, 1, 2, 3), (1, 0, 3, 2), (2, 3, 0, 1), (3, 2, 1, 0))  # quat_mul's
_DIFF_SIGN = ((1, 1, 1, 1), (1, -1, 1, -1), (1, -1, -1, 1), (1, 1, -1, -1))


def quat_mul_conjugate(q1: torch.Tensor, q2: torch.Tensor, rows: slice = slice(None)) -> torch.Tensor:
    """``quat_mul(q1, quat_conjugate(q2))`` (the rotation from ``q2`` to ``q1``) in four kernels;
    ``rows`` picks components (1:4, the vector part) without computing the others."""
    index, sign = _diff_tables(q1.device, q1.dtype)
    return (q1[..., index[rows]] * sign[rows] * q2[..., None, :]).sum(dim=-1)


@functools.lru_cache(maxsize=16)
def _diff_tables(device: torch.device, dtype: torch.dtype) -> tuple[torch.Tensor, torch.Tensor]:
    """Made once per device (a step captured as a CUDA graph may not copy from the host)."""
    return (
        torch.tensor(_DIFF_INDEX, dtype=torch.long, device=device),
        torch.tensor(_DIFF_SIGN, dtype=dtype, device=device),
    )


def rotation_distance(
    object_rot: torch.Tensor, target_rot: torch.Tensor, out: torch.Tensor | None = None
) -> torch.Tensor:
    """The angle [rad] of the rotation between two orientations (w, x, y, z); never negative (into
    ``out`` if given)."""
    vector = quat_mul_conjugate(object_rot, target_rot, rows=slice(1, 4))  # the rotation's vector part
    sine = torch.linalg.vector_norm(vector, dim=-1).clamp_(max=1.0)
    return torch.asin(sine, out=out).mul_(2.0)


def compute_rewards(
    reset_buf: torch.Tensor,
    reset_goal_buf: torch.Tensor,
    successes: torch.Tensor,
    consecutive_successes: torch.Tensor,
    object_pos: torch.Tensor,
    object_rot: torch.Tensor,
    target_pos: torch.Tensor,
    target_rot: torch.Tensor,
    dist_reward_scale: float,
    rot_reward_scale: float,
    rot_eps: float,
    actions: torch.Tensor,
    action_penalty_scale: float,
    success_tolerance: float,
    reach_goal_bonus: float,
    fall_dist: float,
    fall_penalty: float,
    av_factor: float,
    goal_dist: torch.Tensor | None = None,
    rot_dist: torch.Tensor | None = None,
) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor]:
    """Isaac Lab's in-hand reward. Returns the reward, which envs reached their goal, the success counts
    and the running mean of the success counts of the episodes that end in this step. ``goal_dist`` and
    ``rot_dist``, when given, are the distances already computed for this state."""
    if goal_dist is None:
        goal_dist = torch.norm(object_pos - target_pos, p=2, dim=-1)
    if rot_dist is None:
        rot_dist = rotation_distance(object_rot, target_rot)
    # rot_dist is never negative: Isaac Lab's abs() of it changes nothing and is left out
    reward = (
        goal_dist * dist_reward_scale
        + rot_reward_scale / (rot_dist + rot_eps)
        + torch.sum(actions**2, dim=-1) * action_penalty_scale
    )
    goal_reached = (rot_dist <= success_tolerance) | reset_goal_buf
    reached = goal_reached.float()
    successes = successes + reached
    reward = reward + reach_goal_bonus * reached
    fell = goal_dist >= fall_dist
    if fall_penalty != 0:
        reward = reward + fall_penalty * fell.float()

    # running mean over the episodes that end now (the fallen ones included) of their success counts
    consecutive_successes = consecutive_successes.clone()
    update_consecutive_successes(consecutive_successes, successes, (fell | reset_buf).float(), av_factor)
    return reward, goal_reached, successes, consecutive_successes


def update_consecutive_successes(
    consecutive_successes: torch.Tensor, successes: torch.Tensor, resets: torch.Tensor, av_factor: float
) -> None:
    """Isaac Lab's running mean (``av_factor``) of the success counts of the episodes that end now
    (``resets``: 1.0 where one ends), updated in place; unchanged in a step where none ends."""
    num_resets = resets.sum()
    finished_successes = (successes * resets).sum()
    mean = torch.mul(finished_successes, av_factor).div_(num_resets.clamp(min=1.0))
    mean = torch.add(mean, consecutive_successes, alpha=1.0 - av_factor)
    torch.where(num_resets > 0, mean, consecutive_successes, out=consecutive_successes)
