"""ANYmal-C velocity tracking, direct workflow (Isaac Lab's ``Isaac-Velocity-{Flat,Rough}-Anymal-C-Direct-v0``).

The manager-based velocity task written out in one class. Actions (12): joint position targets, 0.5 rad
per unit around the default pose. Observations (48; 235 on rough ground): base linear and angular
velocity, gravity in the base frame, the command, joint positions (relative to the defaults) and
velocities, the 17 x 11 height scan (rough only), the last action. Commands: planar velocity and yaw
rate, each uniform in [-1, 1], drawn once per episode. Rewards (scaled by the step time): velocity and
yaw-rate tracking, penalties on vertical and roll/pitch motion, torques, accelerations, action rate,
thigh contacts and (flat) tilt, a bonus for steps longer than 0.5 s. The episode ends when the base
touches the ground, or after 20 s.
"""

from __future__ import annotations

import torch

import simlab.envs.mdp as mdp
import simlab.sim as sim_utils
from simlab.assets import Articulation, ArticulationCfg
from simlab.envs import DirectRLEnv, DirectRLEnvCfg
from simlab.managers import EventTermCfg as EventTerm
from simlab.managers import SceneEntityCfg
from simlab.robots.anymal import ANYMAL_C_CFG
from simlab.scene import InteractiveSceneCfg
from simlab.sensors import ContactSensor, ContactSensorCfg, RayCaster, RayCasterCfg, patterns
from simlab.sim import SimulationCfg
from simlab.terrains import TerrainImporterCfg
from simlab.terrains.config.rough import ROUGH_TERRAINS_CFG
from simlab.utils import configclass
from simlab.utils.env_mask import masked_copy_

REWARD_TERMS = (
    "track_lin_vel_xy_exp",
    "track_ang_vel_z_exp",
    "lin_vel_z_l2",
    "ang_vel_xy_l2",
    "dof_torques_l2",
    "dof_acc_l2",
    "action_rate_l2",
    "feet_air_time",
    "undesired_contacts",
    "flat_orientation_l2",
)

_GROUND_MATERIAL = sim_utils.RigidBodyMaterialCfg(
    friction_combine_mode="multiply",
    restitution_combine_mode="multiply",
    static_friction=1.0,
    dynamic_friction=1.0,
    restitution=0.0,
)


@configclass
class EventCfg:
    physics_material = EventTerm(
        func=mdp.randomize_rigid_body_material,
        mode="startup",
        params={
            "asset_cfg": SceneEntityCfg("robot", body_names=".*"),
            "static_friction_range": (0.8, 0.8),
            "dynamic_friction_range": (0.6, 0.6),
            "restitution_range": (0.0, 0.0),
            "num_buckets": 64,
        },
    )
    add_base_mass = EventTerm(
        func=mdp.randomize_rigid_body_mass,
        mode="startup",
        params={
            "asset_cfg": SceneEntityCfg("robot", body_names="base"),
            "mass_distribution_params": (-5.0, 5.0),
            "operation": "add",
        },
    )


@configclass
class AnymalCFlatEnvCfg(DirectRLEnvCfg):
    # env
    episode_length_s = 20.0
    decimation = 4
    action_scale = 0.5
    action_space = 12
    observation_space = 48
    state_space = 0

    # simulation
    sim: SimulationCfg = SimulationCfg(dt=1 / 200, render_interval=decimation, physics_material=_GROUND_MATERIAL)
    terrain = TerrainImporterCfg(
        prim_path="/World/ground", terrain_type="plane", collision_group=-1, physics_material=_GROUND_MATERIAL
    )

    # scene
    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=4096, env_spacing=4.0, replicate_physics=True)

    # events
    events: EventCfg = EventCfg()

    # robot
    robot: ArticulationCfg = ANYMAL_C_CFG.replace(prim_path="/World/envs/env_.*/Robot")
    contact_sensor: ContactSensorCfg = ContactSensorCfg(
        prim_path="/World/envs/env_.*/Robot/.*", history_length=3, update_period=0.005, track_air_time=True
    )

    # reward scales
    lin_vel_reward_scale = 1.0
    yaw_rate_reward_scale = 0.5
    z_vel_reward_scale = -2.0
    ang_vel_reward_scale = -0.05
    joint_torque_reward_scale = -2.5e-5
    joint_accel_reward_scale = -2.5e-7
    action_rate_reward_scale = -0.01
    feet_air_time_reward_scale = 0.5
    undesired_contact_reward_scale = -1.0
    flat_orientation_reward_scale = -5.0


@configclass
class AnymalCRoughEnvCfg(AnymalCFlatEnvCfg):
    observation_space = 235  # + the 17 x 11 height scan

    terrain = TerrainImporterCfg(
        prim_path="/World/ground",
        terrain_type="generator",
        terrain_generator=ROUGH_TERRAINS_CFG,
        max_init_terrain_level=9,
        collision_group=-1,
        physics_material=_GROUND_MATERIAL,
    )
    height_scanner = RayCasterCfg(
        prim_path="/World/envs/env_.*/Robot/base",
        offset=RayCasterCfg.OffsetCfg(pos=(0.0, 0.0, 20.0)),
        ray_alignment="yaw",
        pattern_cfg=patterns.GridPatternCfg(resolution=0.1, size=[1.6, 1.0]),
        debug_vis=False,
        mesh_prim_paths=["/World/ground"],
    )

    flat_orientation_reward_scale = 0.0


class AnymalCEnv(DirectRLEnv):
    cfg: AnymalCFlatEnvCfg | AnymalCRoughEnvCfg

    def __init__(self, cfg: AnymalCFlatEnvCfg | AnymalCRoughEnvCfg, render_mode: str | None = None, **kwargs):
        super().__init__(cfg, render_mode, **kwargs)
        self._actions = torch.zeros(self.num_envs, self.cfg.action_space, device=self.device)
        self._previous_actions = torch.zeros_like(self._actions)
        self._processed_actions = self._robot.data.default_joint_pos.clone()
        # planar velocity and yaw-rate command, one per episode
        self._commands = torch.zeros(self.num_envs, 3, device=self.device)

        # logging: episode sums per reward term; the last log lives on the device (no host reads in the step)
        self._episode_sums = torch.zeros(self.num_envs, len(REWARD_TERMS), device=self.device)
        self._log_names = [f"Episode_Reward/{k}" for k in REWARD_TERMS] + [
            "Episode_Termination/base_contact",
            "Episode_Termination/time_out",
        ]
        self._log = torch.zeros(len(self._log_names), device=self.device)

        # body indices on the device once: a captured step may not copy indices from the host
        def body_ids(pattern: str) -> torch.Tensor:
            return torch.tensor(self._contact_sensor.find_bodies(pattern)[0], dtype=torch.long, device=self.device)

        self._base_id = body_ids("base")
        self._feet_ids = body_ids(".*FOOT")
        self._undesired_contact_body_ids = body_ids(".*THIGH")

    def _setup_scene(self):
        self._robot = Articulation(self.cfg.robot)
        self.scene.articulations["robot"] = self._robot
        self._contact_sensor = ContactSensor(self.cfg.contact_sensor)
        self.scene.sensors["contact_sensor"] = self._contact_sensor
        self._height_scanner = None
        if isinstance(self.cfg, AnymalCRoughEnvCfg):
            self._height_scanner = RayCaster(self.cfg.height_scanner)
            self.scene.sensors["height_scanner"] = self._height_scanner
        self.cfg.terrain.num_envs = self.scene.cfg.num_envs
        self.cfg.terrain.env_spacing = self.scene.cfg.env_spacing
        self._terrain = self.cfg.terrain.class_type(self.cfg.terrain)
        self.scene.clone_environments(copy_from_source=False)
        light_cfg = sim_utils.DomeLightCfg(intensity=2000.0, color=(0.75, 0.75, 0.75))
        light_cfg.func("/World/Light", light_cfg)

    def _pre_physics_step(self, actions: torch.Tensor):
        self._actions = actions.clone()
        self._processed_actions = self.cfg.action_scale * self._actions + self._robot.data.default_joint_pos

    def _apply_action(self):
        self._robot.set_joint_position_target(self._processed_actions)

    def _get_observations(self) -> dict:
        self._previous_actions = self._actions.clone()
        data = self._robot.data
        parts = [
            data.root_lin_vel_b,
            data.root_ang_vel_b,
            data.projected_gravity_b,
            self._commands,
            data.joint_pos - data.default_joint_pos,
            data.joint_vel,
        ]
        if self._height_scanner is not None:
            scan = self._height_scanner.data
            parts.append((scan.pos_w[:, 2].unsqueeze(1) - scan.ray_hits_w[..., 2] - 0.5).clip(-1.0, 1.0))
        parts.append(self._actions)
        return {"policy": torch.cat(parts, dim=-1)}

    def _get_rewards(self) -> torch.Tensor:
        data, contacts = self._robot.data, self._contact_sensor
        lin_vel_error = torch.sum(torch.square(self._commands[:, :2] - data.root_lin_vel_b[:, :2]), dim=1)
        yaw_rate_error = torch.square(self._commands[:, 2] - data.root_ang_vel_b[:, 2])
        # steps: each foot landing after more than 0.5 s in the air earns the excess (less, costs), when asked to walk
        first_contact = contacts.compute_first_contact(self.step_dt)[:, self._feet_ids]
        last_air_time = contacts.data.last_air_time[:, self._feet_ids]
        walking = torch.linalg.norm(self._commands[:, :2], dim=1) > 0.1
        air_time = torch.sum((last_air_time - 0.5) * first_contact, dim=1) * walking
        # thighs touching anything (more than 1 N over the sensor's history)
        thigh_forces = contacts.data.net_forces_w_history[:, :, self._undesired_contact_body_ids]
        thigh_contacts = torch.sum(torch.linalg.norm(thigh_forces, dim=-1).amax(dim=1) > 1.0, dim=1)
        terms = {
            "track_lin_vel_xy_exp": (torch.exp(-lin_vel_error / 0.25), self.cfg.lin_vel_reward_scale),
            "track_ang_vel_z_exp": (torch.exp(-yaw_rate_error / 0.25), self.cfg.yaw_rate_reward_scale),
            "lin_vel_z_l2": (torch.square(data.root_lin_vel_b[:, 2]), self.cfg.z_vel_reward_scale),
            "ang_vel_xy_l2": (
                torch.sum(torch.square(data.root_ang_vel_b[:, :2]), dim=1),
                self.cfg.ang_vel_reward_scale,
            ),
            "dof_torques_l2": (torch.sum(torch.square(data.applied_torque), dim=1), self.cfg.joint_torque_reward_scale),
            "dof_acc_l2": (torch.sum(torch.square(data.joint_acc), dim=1), self.cfg.joint_accel_reward_scale),
            "action_rate_l2": (
                torch.sum(torch.square(self._actions - self._previous_actions), dim=1),
                self.cfg.action_rate_reward_scale,
            ),
            "feet_air_time": (air_time, self.cfg.feet_air_time_reward_scale),
            "undesired_contacts": (thigh_contacts.float(), self.cfg.undesired_contact_reward_scale),
            "flat_orientation_l2": (
                torch.sum(torch.square(data.projected_gravity_b[:, :2]), dim=1),
                self.cfg.flat_orientation_reward_scale,
            ),
        }
        rewards = torch.stack([terms[name][0] * terms[name][1] * self.step_dt for name in REWARD_TERMS], dim=1)
        self._episode_sums += rewards
        return rewards.sum(dim=1)

    def _get_dones(self) -> tuple[torch.Tensor, torch.Tensor]:
        time_out = self.episode_length_buf >= self.max_episode_length - 1
        base_forces = self._contact_sensor.data.net_forces_w_history[:, :, self._base_id]
        died = torch.any(torch.linalg.norm(base_forces, dim=-1).amax(dim=1) > 1.0, dim=1)
        return died, time_out

    def _reset_mask(self, env_mask: torch.Tensor):
        self._log_finished_episodes(env_mask)
        super()._reset_mask(env_mask)
        # spread out the resets when every env resets at once (avoids synchronised episodes in training)
        spread = torch.randint_like(self.episode_length_buf, high=int(self.max_episode_length))
        masked_copy_(self.episode_length_buf, env_mask.all().expand(self.num_envs), spread)
        masked_copy_(self._actions, env_mask, 0.0)
        masked_copy_(self._previous_actions, env_mask, 0.0)
        masked_copy_(self._commands, env_mask, torch.empty_like(self._commands).uniform_(-1.0, 1.0))
        # the robot at its default state above its terrain origin
        data = self._robot.data
        default_root_state = data.default_root_state.clone()
        default_root_state[:, :3] += self._terrain.env_origins
        self._robot.write_root_pose_to_sim(default_root_state[:, :7], env_mask)
        self._robot.write_root_velocity_to_sim(default_root_state[:, 7:], env_mask)
        self._robot.write_joint_state_to_sim(data.default_joint_pos, data.default_joint_vel, None, env_mask)

    def _log_finished_episodes(self, env_mask: torch.Tensor) -> None:
        """Means over the envs in ``env_mask`` (Isaac Lab's log); kept as they were if the mask is empty."""
        finished = env_mask.float()
        count = finished.sum()
        log = torch.cat(
            [
                (self._episode_sums * finished[:, None]).sum(dim=0) / count.clamp(min=1.0) / self.max_episode_length_s,
                torch.stack(
                    [(self.reset_terminated & env_mask).sum().float(), (self.reset_time_outs & env_mask).sum().float()]
                ),
            ]
        )
        masked_copy_(self._log, (count > 0).expand(len(self._log_names)), log)
        masked_copy_(self._episode_sums, env_mask, 0.0)

    def step(self, action: torch.Tensor):
        obs, reward, terminated, truncated, extras = super().step(action)
        # a snapshot of the device-side log (Isaac Lab refreshes it in steps where some env finished)
        extras["log"].update(zip(self._log_names, self._log.clone().unbind()))
        return obs, reward, terminated, truncated, extras
