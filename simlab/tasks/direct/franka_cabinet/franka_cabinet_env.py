"""Franka cabinet, direct workflow (Isaac Lab's ``Isaac-Franka-Cabinet-Direct-v0``): open the top drawer.

The Franka stands 1 m in front of the cabinet, facing it. Actions (9: the arm's seven joints and the
two fingers, in [-1, 1]) move the joint position targets at ``action_scale * speed_scale`` rad/s
(fingers a tenth as fast). Observations (23): the joint positions scaled to [-1, 1] within their
limits, joint velocities times ``dof_velocity_scale``, the vector from the grasp point between the
fingers to the drawer handle, the drawer's opening and its speed. The reward (Isaac Lab's terms):
closeness of the grasp point to the handle, alignment of the gripper with the handle (fingers above
and below it), the drawer's opening, fingers on the wrong side of the handle, squared actions, and
bonuses for openings past 1, 20 and 35 cm. An episode ends with the drawer open past 39 cm or after
500 steps (8.3 s).

One change from Isaac Lab: a reset also sets the joint position targets the actions integrate to the
drawn joint positions (Isaac Lab keeps the previous episode's targets in its buffer, so the arm jumps
back to where the last episode left it).
"""

from __future__ import annotations

import torch

import simlab.sim as sim_utils
from simlab.assets import Articulation, ArticulationCfg
from simlab.envs import DirectRLEnv, DirectRLEnvCfg, ViewerCfg
from simlab.robots.cabinet import SEKTION_CABINET_CFG
from simlab.robots.franka import FRANKA_PANDA_CFG
from simlab.scene import InteractiveSceneCfg
from simlab.sim import MujocoCfg, SimulationCfg
from simlab.sim.spawners.from_files import GroundPlaneCfg, spawn_ground_plane
from simlab.utils import configclass
from simlab.utils.env_mask import masked_copy_
from simlab.utils.math import combine_frame_transforms, quat_apply, quat_inv, sample_uniform

DRAWER_OPENING_OBS = 21
"""Column of the policy observation that holds the top drawer's opening [m]."""


@configclass
class FrankaCabinetEnvCfg(DirectRLEnvCfg):
    # env
    episode_length_s = 8.3333  # 500 steps
    decimation = 2
    action_space = 9
    observation_space = 23
    state_space = 0

    # simulation: elliptic friction cones with impratio 10 make friction stiff enough for a pinch grasp
    # to hold the handle while pulling (with pyramidal cones and impratio 1 the handle slipped out of
    # the scripted grasp of tests/test_franka_cabinet.py after 15-25 cm); GPU buffers per world sized
    # for condim rows per contact (4 at the finger pads)
    sim: SimulationCfg = SimulationCfg(
        dt=1 / 120,
        render_interval=decimation,
        mujoco=MujocoCfg(cone="elliptic", impratio=10.0, nconmax=48, njmax=256),
    )

    # scene
    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=4096, env_spacing=3.0, replicate_physics=True)
    # videos look at env 0's robot and drawer (Isaac Lab keeps the default far view)
    viewer: ViewerCfg = ViewerCfg(eye=(2.2, 1.6, 1.4), lookat=(0.5, 0.0, 0.6), origin_type="env")

    # robot: 1 m in front of the cabinet, turned to face it
    robot: ArticulationCfg = FRANKA_PANDA_CFG.replace(
        prim_path="/World/envs/env_.*/Robot",
        init_state=ArticulationCfg.InitialStateCfg(
            joint_pos={
                "panda_joint1": 1.157,
                "panda_joint2": -1.066,
                "panda_joint3": -0.155,
                "panda_joint4": -2.239,
                "panda_joint5": -1.841,
                "panda_joint6": 1.003,
                "panda_joint7": 0.469,
                "panda_finger_joint.*": 0.035,
            },
            pos=(1.0, 0.0, 0.0),
            rot=(0.0, 0.0, 0.0, 1.0),
        ),
    )

    # cabinet
    cabinet: ArticulationCfg = SEKTION_CABINET_CFG.replace(prim_path="/World/envs/env_.*/Cabinet")

    # ground plane
    terrain = GroundPlaneCfg(
        physics_material=sim_utils.RigidBodyMaterialCfg(static_friction=1.0, dynamic_friction=1.0, restitution=0.0)
    )

    action_scale = 7.5
    dof_velocity_scale = 0.1
    reset_joint_noise = 0.125  # joint positions at reset: default +- this [rad]

    # reward scales
    dist_reward_scale = 1.5
    rot_reward_scale = 1.5
    open_reward_scale = 10.0
    action_penalty_scale = 0.05
    finger_reward_scale = 2.0

    # where the grasp frames sit: the drawer's grip point in the drawer_top frame, and how far the
    # robot's grasp point lies from the fingers' midpoint along panda_link7's y axis (Isaac Lab's)
    drawer_local_grasp_pos = (0.3, 0.01, 0.0)
    robot_grasp_offset = (0.0, 0.04, 0.0)
    open_termination = 0.39  # drawer opening that ends the episode [m]


class FrankaCabinetEnv(DirectRLEnv):
    cfg: FrankaCabinetEnvCfg

    def __init__(self, cfg: FrankaCabinetEnvCfg, render_mode: str | None = None, **kwargs):
        super().__init__(cfg, render_mode, **kwargs)
        self.dt = self.cfg.sim.dt * self.cfg.decimation
        n, device = self.num_envs, self.device

        self.robot_dof_lower_limits = self._robot.data.soft_joint_pos_limits[0, :, 0].to(device=device)
        self.robot_dof_upper_limits = self._robot.data.soft_joint_pos_limits[0, :, 1].to(device=device)
        self.robot_dof_speed_scales = torch.ones_like(self.robot_dof_lower_limits)
        self.robot_dof_speed_scales[self._robot.find_joints("panda_finger_joint.*")[0]] = 0.1
        self.robot_dof_targets = torch.zeros((n, self._robot.num_joints), device=device)

        self.hand_link_idx = self._robot.find_bodies("panda_link7")[0][0]
        self.left_finger_link_idx = self._robot.find_bodies("panda_leftfinger")[0][0]
        self.right_finger_link_idx = self._robot.find_bodies("panda_rightfinger")[0][0]
        self.drawer_link_idx = self._cabinet.find_bodies("drawer_top")[0][0]
        self.drawer_joint_idx = self._cabinet.find_joints("drawer_top_joint")[0][0]

        # The robot's grasp frame in panda_link7's frame: the fingers' midpoint with the left
        # finger's orientation, measured on env 0's spawn pose (as Isaac Lab reads it from the stage).
        body_pos, body_quat = self._robot.data.body_pos_w[0], self._robot.data.body_quat_w[0]
        hand_pos, hand_rot = body_pos[self.hand_link_idx], body_quat[self.hand_link_idx]
        finger_pos = 0.5 * (body_pos[self.left_finger_link_idx] + body_pos[self.right_finger_link_idx])
        finger_rot = body_quat[self.left_finger_link_idx]
        hand_rot_inv = quat_inv(hand_rot)
        local_pos, local_rot = combine_frame_transforms(
            -quat_apply(hand_rot_inv, hand_pos), hand_rot_inv, finger_pos, finger_rot
        )
        local_pos = local_pos + torch.tensor(self.cfg.robot_grasp_offset, device=device)
        self.robot_local_grasp_pos = local_pos.repeat((n, 1))
        self.robot_local_grasp_rot = local_rot.repeat((n, 1))
        self.drawer_local_grasp_pos = torch.tensor(self.cfg.drawer_local_grasp_pos, device=device).repeat((n, 1))
        self.drawer_local_grasp_rot = torch.tensor([1.0, 0.0, 0.0, 0.0], device=device).repeat((n, 1))

        self.gripper_forward_axis = torch.tensor([0.0, 0.0, 1.0], device=device).repeat((n, 1))
        self.drawer_inward_axis = torch.tensor([-1.0, 0.0, 0.0], device=device).repeat((n, 1))
        self.gripper_up_axis = torch.tensor([0.0, 1.0, 0.0], device=device).repeat((n, 1))
        self.drawer_up_axis = torch.tensor([0.0, 0.0, 1.0], device=device).repeat((n, 1))

        self.robot_grasp_rot = torch.zeros((n, 4), device=device)
        self.robot_grasp_pos = torch.zeros((n, 3), device=device)
        self.drawer_grasp_rot = torch.zeros((n, 4), device=device)
        self.drawer_grasp_pos = torch.zeros((n, 3), device=device)
        self._compute_intermediate_values()
        self._log_names = list(REWARD_TERMS)
        self._log = torch.zeros(len(self._log_names), device=device)

    def _setup_scene(self):
        self._robot = Articulation(self.cfg.robot)
        self._cabinet = Articulation(self.cfg.cabinet)
        self.scene.articulations["robot"] = self._robot
        self.scene.articulations["cabinet"] = self._cabinet
        spawn_ground_plane(prim_path="/World/ground", cfg=self.cfg.terrain)
        light_cfg = sim_utils.DomeLightCfg(intensity=2000.0, color=(0.75, 0.75, 0.75))
        light_cfg.func("/World/Light", light_cfg)

    def step(self, action: torch.Tensor):
        obs, reward, terminated, truncated, extras = super().step(action)
        # a snapshot of the reward terms' means over the envs in this step (Isaac Lab's log keys)
        extras["log"].update(zip(self._log_names, self._log.clone().unbind()))
        return obs, reward, terminated, truncated, extras

    # pre-physics step calls

    def _pre_physics_step(self, actions: torch.Tensor):
        self.actions = actions.clone().clamp(-1.0, 1.0)
        targets = self.robot_dof_targets + self.robot_dof_speed_scales * self.dt * self.actions * self.cfg.action_scale
        self.robot_dof_targets[:] = torch.clamp(targets, self.robot_dof_lower_limits, self.robot_dof_upper_limits)

    def _apply_action(self):
        self._robot.set_joint_position_target(self.robot_dof_targets)

    # post-physics step calls

    def _get_dones(self) -> tuple[torch.Tensor, torch.Tensor]:
        terminated = self._cabinet.data.joint_pos[:, self.drawer_joint_idx] > self.cfg.open_termination
        truncated = self.episode_length_buf >= self.max_episode_length - 1
        return terminated, truncated

    def _get_rewards(self) -> torch.Tensor:
        # refresh the grasp frames after the physics steps
        self._compute_intermediate_values()
        rewards, terms = compute_rewards(
            self.actions,
            self._cabinet.data.joint_pos[:, self.drawer_joint_idx],
            self.robot_grasp_pos,
            self.drawer_grasp_pos,
            self.robot_grasp_rot,
            self.drawer_grasp_rot,
            self._robot.data.body_pos_w[:, self.left_finger_link_idx],
            self._robot.data.body_pos_w[:, self.right_finger_link_idx],
            self.gripper_forward_axis,
            self.drawer_inward_axis,
            self.gripper_up_axis,
            self.drawer_up_axis,
            self.cfg.dist_reward_scale,
            self.cfg.rot_reward_scale,
            self.cfg.open_reward_scale,
            self.cfg.action_penalty_scale,
            self.cfg.finger_reward_scale,
        )
        # the terms' means, kept on the device (a captured step reads nothing back); step() reports them
        self._log.copy_(torch.stack([value.mean() for value in terms.values()]))
        return rewards

    def _reset_mask(self, env_mask: torch.Tensor):
        super()._reset_mask(env_mask)
        # robot: the default pose plus uniform noise, drawn for every env and written where env_mask is set
        noise = self.cfg.reset_joint_noise
        joint_pos = self._robot.data.default_joint_pos + sample_uniform(
            -noise, noise, (self.num_envs, self._robot.num_joints), self.device
        )
        joint_pos = torch.clamp(joint_pos, self.robot_dof_lower_limits, self.robot_dof_upper_limits)
        joint_vel = torch.zeros_like(joint_pos)
        self._robot.set_joint_position_target(joint_pos, env_ids=env_mask)
        self._robot.write_joint_state_to_sim(joint_pos, joint_vel, env_ids=env_mask)
        masked_copy_(self.robot_dof_targets, env_mask, joint_pos)

        # cabinet: every drawer and door closed
        zeros = torch.zeros((self.num_envs, self._cabinet.num_joints), device=self.device)
        self._cabinet.write_joint_state_to_sim(zeros, zeros, env_ids=env_mask)

        # the observations after a reset read the new grasp frames
        self._compute_intermediate_values()

    def _get_observations(self) -> dict:
        dof_pos_scaled = (
            2.0
            * (self._robot.data.joint_pos - self.robot_dof_lower_limits)
            / (self.robot_dof_upper_limits - self.robot_dof_lower_limits)
            - 1.0
        )
        to_target = self.drawer_grasp_pos - self.robot_grasp_pos
        obs = torch.cat(
            (
                dof_pos_scaled,
                self._robot.data.joint_vel * self.cfg.dof_velocity_scale,
                to_target,
                self._cabinet.data.joint_pos[:, self.drawer_joint_idx].unsqueeze(-1),
                self._cabinet.data.joint_vel[:, self.drawer_joint_idx].unsqueeze(-1),
            ),
            dim=-1,
        )
        return {"policy": torch.clamp(obs, -5.0, 5.0)}

    # auxiliary methods

    def _compute_intermediate_values(self) -> None:
        """The robot's and the drawer's grasp frames in the world, for every env."""
        hand_pos = self._robot.data.body_pos_w[:, self.hand_link_idx]
        hand_rot = self._robot.data.body_quat_w[:, self.hand_link_idx]
        drawer_pos = self._cabinet.data.body_pos_w[:, self.drawer_link_idx]
        drawer_rot = self._cabinet.data.body_quat_w[:, self.drawer_link_idx]
        robot_pos, robot_rot = combine_frame_transforms(
            hand_pos, hand_rot, self.robot_local_grasp_pos, self.robot_local_grasp_rot
        )
        drawer_grasp_pos, drawer_grasp_rot = combine_frame_transforms(
            drawer_pos, drawer_rot, self.drawer_local_grasp_pos, self.drawer_local_grasp_rot
        )
        self.robot_grasp_pos.copy_(robot_pos)
        self.robot_grasp_rot.copy_(robot_rot)
        self.drawer_grasp_pos.copy_(drawer_grasp_pos)
        self.drawer_grasp_rot.copy_(drawer_grasp_rot)


REWARD_TERMS = (
    "dist_reward",
    "rot_reward",
    "open_reward",
    "action_penalty",
    "left_finger_distance_reward",
    "right_finger_distance_reward",
    "finger_dist_penalty",
)
"""The scaled reward terms :func:`compute_rewards` returns, in Isaac Lab's names (its ``extras["log"]`` keys)."""


def compute_rewards(
    actions: torch.Tensor,
    drawer_opening: torch.Tensor,
    franka_grasp_pos: torch.Tensor,
    drawer_grasp_pos: torch.Tensor,
    franka_grasp_rot: torch.Tensor,
    drawer_grasp_rot: torch.Tensor,
    franka_lfinger_pos: torch.Tensor,
    franka_rfinger_pos: torch.Tensor,
    gripper_forward_axis: torch.Tensor,
    drawer_inward_axis: torch.Tensor,
    gripper_up_axis: torch.Tensor,
    drawer_up_axis: torch.Tensor,
    dist_reward_scale: float,
    rot_reward_scale: float,
    open_reward_scale: float,
    action_penalty_scale: float,
    finger_reward_scale: float,
) -> tuple[torch.Tensor, dict[str, torch.Tensor]]:
    """Isaac Lab's cabinet reward; returns the total (num_envs,) and its scaled terms per env."""
    # distance from the grasp point to the handle: 1 / (1 + d^2), squared, doubled within 2 cm
    d = torch.linalg.norm(franka_grasp_pos - drawer_grasp_pos, ord=2, dim=-1)
    dist_reward = (1.0 / (1.0 + d**2)) ** 2
    dist_reward = torch.where(d <= 0.02, dist_reward * 2, dist_reward)

    # the gripper's forward axis into the drawer, its up axis (finger to finger) along the drawer's up
    axis1 = quat_apply(franka_grasp_rot, gripper_forward_axis)
    axis2 = quat_apply(drawer_grasp_rot, drawer_inward_axis)
    axis3 = quat_apply(franka_grasp_rot, gripper_up_axis)
    axis4 = quat_apply(drawer_grasp_rot, drawer_up_axis)
    dot1 = (axis1 * axis2).sum(dim=-1)
    dot2 = (axis3 * axis4).sum(dim=-1)
    rot_reward = 0.5 * (torch.sign(dot1) * dot1**2 + torch.sign(dot2) * dot2**2)

    action_penalty = torch.sum(actions**2, dim=-1)
    open_reward = drawer_opening

    # the left finger belongs above the handle, the right one below
    lfinger_dist = franka_lfinger_pos[:, 2] - drawer_grasp_pos[:, 2]
    rfinger_dist = drawer_grasp_pos[:, 2] - franka_rfinger_pos[:, 2]
    finger_dist_penalty = torch.clamp(lfinger_dist, max=0.0) + torch.clamp(rfinger_dist, max=0.0)

    terms = {
        "dist_reward": dist_reward_scale * dist_reward,
        "rot_reward": rot_reward_scale * rot_reward,
        "open_reward": open_reward_scale * open_reward,
        "action_penalty": -action_penalty_scale * action_penalty,
        "left_finger_distance_reward": finger_reward_scale * lfinger_dist,
        "right_finger_distance_reward": finger_reward_scale * rfinger_dist,
        "finger_dist_penalty": finger_reward_scale * finger_dist_penalty,
    }
    rewards = (
        terms["dist_reward"]
        + terms["rot_reward"]
        + terms["open_reward"]
        + terms["finger_dist_penalty"]
        + terms["action_penalty"]
    )
    # bonuses for opening the drawer properly
    rewards = rewards + 0.25 * (
        (drawer_opening > 0.01).float() + (drawer_opening > 0.2).float() + (drawer_opening > 0.35).float()
    )
    return rewards, terms


@configclass
class FrankaCabinetEnvCfg_PLAY(FrankaCabinetEnvCfg):
    """Fewer envs, for watching a trained policy (Isaac Lab registers no Play variant of this task)."""

    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=50, env_spacing=3.0, replicate_physics=True)
