"""Run towards a far target without falling: the shared base of the direct ant and humanoid tasks.

Isaac Lab's ``LocomotionEnv`` (from IsaacGymEnvs). Every joint is torque-driven:
``torque = action_scale * gear * action``. The reward adds progress towards the target (the change
of ``-distance / dt``), an alive bonus, an upright bonus, a heading bonus, and subtracts action,
energy and joint-limit costs; a fallen robot (torso below ``termination_height``) gets
``death_cost`` instead. Observations (``12 + 3 * num_joints``): torso height, torso-frame linear and
angular velocity, yaw, roll, angle to target, up and heading projections, joint positions scaled to
[-1, 1] by their limits, joint velocities, and the last action.
"""

from __future__ import annotations

import torch

import simlab.sim as sim_utils
from simlab.assets import Articulation
from simlab.envs import DirectRLEnv, DirectRLEnvCfg
from simlab.sim.spawners.from_files import spawn_ground_plane
from simlab.terrains import TerrainImporterCfg
from simlab.utils.env_mask import masked_copy_
from simlab.utils.math import quat_conjugate, scale_transform
from simlab.utils.string import resolve_matching_names_values
from simlab.utils.torch_utils.rotations import compute_heading_and_up, compute_rot, normalize_angle


class LocomotionEnv(DirectRLEnv):
    """Needs in its config: ``robot``, ``terrain``, ``action_scale``, ``joint_gears`` and the reward weights
    of ``compute_rewards``. ``terrain`` is a ground plane's cfg, or a ``TerrainImporterCfg`` (Isaac Lab's
    ant and humanoid configs give one with ``terrain_type="plane"``).

    ``joint_gears`` is either a list in the robot's joint order (Isaac Lab's: by depth in the tree) or a dict
    ``{joint name or regex: gear}``, which does not depend on the order.
    """

    cfg: DirectRLEnvCfg

    def __init__(self, cfg: DirectRLEnvCfg, render_mode: str | None = None, **kwargs):
        super().__init__(cfg, render_mode, **kwargs)

        self.action_scale = self.cfg.action_scale
        self._joint_dof_idx, _ = self.robot.find_joints(".*")
        self.joint_gears = resolve_joint_gears(self.cfg.joint_gears, self.robot.joint_names, self.device)
        self.motor_effort_ratio = torch.ones_like(self.joint_gears)

        n, dev = self.num_envs, self.device
        self.potentials = torch.zeros(n, dtype=torch.float32, device=dev)
        self.prev_potentials = torch.zeros_like(self.potentials)
        self.targets = torch.tensor([1000.0, 0.0, 0.0], device=dev).repeat(n, 1) + self.scene.env_origins
        self.start_rotation = torch.tensor([1.0, 0.0, 0.0, 0.0], device=dev)
        self.up_vec = torch.tensor([0.0, 0.0, 1.0], device=dev).repeat(n, 1)
        self.heading_vec = torch.tensor([1.0, 0.0, 0.0], device=dev).repeat(n, 1)
        self.inv_start_rot = quat_conjugate(self.start_rotation).repeat(n, 1)
        self.basis_vec0 = self.heading_vec.clone()
        self.basis_vec1 = self.up_vec.clone()
        self._compute_intermediate_values()

    def _setup_scene(self):
        self.robot = Articulation(self.cfg.robot)
        terrain = self.cfg.terrain
        if isinstance(terrain, TerrainImporterCfg):
            terrain.num_envs, terrain.env_spacing = self.scene.cfg.num_envs, self.scene.cfg.env_spacing
            self.terrain = terrain.class_type(terrain)
        else:
            spawn_ground_plane(prim_path="/World/ground", cfg=terrain)
        self.scene.articulations["robot"] = self.robot
        light_cfg = sim_utils.DomeLightCfg(intensity=2000.0, color=(0.75, 0.75, 0.75))
        light_cfg.func("/World/Light", light_cfg)

    def _pre_physics_step(self, actions: torch.Tensor):
        self.actions = actions.clone()

    def _apply_action(self):
        forces = self.action_scale * self.joint_gears * self.actions
        self.robot.set_joint_effort_target(forces, joint_ids=self._joint_dof_idx)

    def _compute_intermediate_values(self):
        data = self.robot.data
        self.torso_position, self.torso_rotation = data.root_pos_w, data.root_quat_w
        self.velocity, self.ang_velocity = data.root_lin_vel_w, data.root_ang_vel_w
        self.dof_pos, self.dof_vel = data.joint_pos, data.joint_vel
        (
            self.up_proj,
            self.heading_proj,
            self.up_vec,
            self.heading_vec,
            self.vel_loc,
            self.angvel_loc,
            self.roll,
            self.pitch,
            self.yaw,
            self.angle_to_target,
            self.dof_pos_scaled,
            self.prev_potentials,
            self.potentials,
        ) = compute_intermediate_values(
            self.targets,
            self.torso_position,
            self.torso_rotation,
            self.velocity,
            self.ang_velocity,
            self.dof_pos,
            data.soft_joint_pos_limits[0, :, 0],
            data.soft_joint_pos_limits[0, :, 1],
            self.inv_start_rot,
            self.basis_vec0,
            self.basis_vec1,
            self.potentials,
            self.prev_potentials,
            self.cfg.sim.dt,
        )

    def _get_observations(self) -> dict:
        obs = torch.cat(
            (
                self.torso_position[:, 2].view(-1, 1),
                self.vel_loc,
                self.angvel_loc * self.cfg.angular_velocity_scale,
                normalize_angle(self.yaw).unsqueeze(-1),
                normalize_angle(self.roll).unsqueeze(-1),
                normalize_angle(self.angle_to_target).unsqueeze(-1),
                self.up_proj.unsqueeze(-1),
                self.heading_proj.unsqueeze(-1),
                self.dof_pos_scaled,
                self.dof_vel * self.cfg.dof_vel_scale,
                self.actions,
            ),
            dim=-1,
        )
        return {"policy": obs}

    def _get_rewards(self) -> torch.Tensor:
        return compute_rewards(
            self.actions,
            self.reset_terminated,
            self.cfg.up_weight,
            self.cfg.heading_weight,
            self.heading_proj,
            self.up_proj,
            self.dof_vel,
            self.dof_pos_scaled,
            self.potentials,
            self.prev_potentials,
            self.cfg.actions_cost_scale,
            self.cfg.energy_cost_scale,
            self.cfg.dof_vel_scale,
            self.cfg.death_cost,
            self.cfg.alive_reward_scale,
            self.motor_effort_ratio,
        )

    def _get_dones(self) -> tuple[torch.Tensor, torch.Tensor]:
        self._compute_intermediate_values()
        time_out = self.episode_length_buf >= self.max_episode_length - 1
        died = self.torso_position[:, 2] < self.cfg.termination_height
        return died, time_out

    def _reset_mask(self, env_mask: torch.Tensor):
        super()._reset_mask(env_mask)
        # Initial states are computed for every env and written where env_mask is set.
        data = self.robot.data
        default_root_state = data.default_root_state.clone()
        default_root_state[:, :3] += self.scene.env_origins

        self.robot.write_root_pose_to_sim(default_root_state[:, :7], env_mask)
        self.robot.write_root_velocity_to_sim(default_root_state[:, 7:], env_mask)
        self.robot.write_joint_state_to_sim(data.default_joint_pos, data.default_joint_vel, None, env_mask)

        to_target = self.targets - default_root_state[:, :3]
        to_target[:, 2] = 0.0
        masked_copy_(self.potentials, env_mask, -torch.norm(to_target, p=2, dim=-1) / self.cfg.sim.dt)

        self._compute_intermediate_values()


def resolve_joint_gears(gears: list[float] | dict[str, float], joint_names: list[str], device) -> torch.Tensor:
    """Gears per joint, in joint order, from a list (joint order) or a dict of names / regexes."""
    if isinstance(gears, dict):
        ids, _, values = resolve_matching_names_values(gears, joint_names)
        missing = sorted(set(range(len(joint_names))) - set(ids))
        if missing:
            raise ValueError(f"joint_gears gives no gear for joints {[joint_names[i] for i in missing]}")
        out = torch.zeros(len(joint_names), device=device)
        out[torch.tensor(ids, device=device)] = torch.tensor(values, dtype=torch.float32, device=device)
        return out
    if len(gears) != len(joint_names):
        raise ValueError(
            f"joint_gears has {len(gears)} values but the robot has {len(joint_names)} joints {joint_names}; "
            "give one gear per joint in this order, or a dict {joint name or regex: gear}"
        )
    return torch.tensor(gears, dtype=torch.float32, device=device)


@torch.jit.script
def compute_rewards(
    actions: torch.Tensor,
    reset_terminated: torch.Tensor,
    up_weight: float,
    heading_weight: float,
    heading_proj: torch.Tensor,
    up_proj: torch.Tensor,
    dof_vel: torch.Tensor,
    dof_pos_scaled: torch.Tensor,
    potentials: torch.Tensor,
    prev_potentials: torch.Tensor,
    actions_cost_scale: float,
    energy_cost_scale: float,
    dof_vel_scale: float,
    death_cost: float,
    alive_reward_scale: float,
    motor_effort_ratio: torch.Tensor,
):
    heading_weight_tensor = torch.ones_like(heading_proj) * heading_weight
    heading_reward = torch.where(heading_proj > 0.8, heading_weight_tensor, heading_weight * heading_proj / 0.8)

    # aligning up axis of robot and environment
    up_reward = torch.zeros_like(heading_reward)
    up_reward = torch.where(up_proj > 0.93, up_reward + up_weight, up_reward)

    # energy penalty for movement
    actions_cost = torch.sum(actions**2, dim=-1)
    electricity_cost = torch.sum(
        torch.abs(actions * dof_vel * dof_vel_scale) * motor_effort_ratio.unsqueeze(0),
        dim=-1,
    )

    # dof at limit cost
    dof_at_limit_cost = torch.sum(dof_pos_scaled > 0.98, dim=-1)

    # reward for duration of staying alive
    alive_reward = torch.ones_like(potentials) * alive_reward_scale
    progress_reward = potentials - prev_potentials

    total_reward = (
        progress_reward
        + alive_reward
        + up_reward
        + heading_reward
        - actions_cost_scale * actions_cost
        - energy_cost_scale * electricity_cost
        - dof_at_limit_cost
    )
    # adjust reward for fallen agents
    total_reward = torch.where(reset_terminated, torch.ones_like(total_reward) * death_cost, total_reward)
    return total_reward


def compute_intermediate_values(
    targets: torch.Tensor,
    torso_position: torch.Tensor,
    torso_rotation: torch.Tensor,
    velocity: torch.Tensor,
    ang_velocity: torch.Tensor,
    dof_pos: torch.Tensor,
    dof_lower_limits: torch.Tensor,
    dof_upper_limits: torch.Tensor,
    inv_start_rot: torch.Tensor,
    basis_vec0: torch.Tensor,
    basis_vec1: torch.Tensor,
    potentials: torch.Tensor,
    prev_potentials: torch.Tensor,
    dt: float,
):
    """Heading/up projections, torso-frame velocities, Euler angles, scaled joints, potentials."""
    to_target = targets - torso_position
    to_target[:, 2] = 0.0

    # heading and up: the torso's x and z axes, projected on the target direction and on world z
    torso_quat, up_proj, heading_proj, up_vec, heading_vec = compute_heading_and_up(
        torso_rotation, inv_start_rot, to_target, basis_vec0, basis_vec1, 2
    )
    vel_loc, angvel_loc, roll, pitch, yaw, angle_to_target = compute_rot(
        torso_quat, velocity, ang_velocity, targets, torso_position
    )

    # joint positions mapped from their limits to [-1, 1]
    dof_pos_scaled = scale_transform(dof_pos, dof_lower_limits, dof_upper_limits)

    prev_potentials[:] = potentials
    potentials = -torch.norm(to_target, p=2, dim=-1) / dt

    return (
        up_proj,
        heading_proj,
        up_vec,
        heading_vec,
        vel_loc,
        angvel_loc,
        roll,
        pitch,
        yaw,
        angle_to_target,
        dof_pos_scaled,
        prev_potentials,
        potentials,
    )
