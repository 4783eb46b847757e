"""Planar pose commands for a legged base: a goal position around the env's origin and a heading
(Isaac Lab's ``UniformPose2dCommand``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils
from simlab.managers.command_manager import CommandTerm
from simlab.markers import VisualizationMarkers
from simlab.utils.env_mask import masked_copy_

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

    from .commands_cfg import UniformPose2dCommandCfg


class UniformPose2dCommand(CommandTerm):
    """``(x, y, z, heading)`` of the goal in the base's yaw frame, re-targeted every step.

    The goal is drawn uniformly around the env's origin at the robot's default root height; its heading
    is drawn uniformly or, with ``simple_heading``, faces the goal (or away from it, whichever is closer
    to the current heading). Metrics: ``error_pos_2d`` (m) and ``error_heading`` (rad).
    """

    cfg: UniformPose2dCommandCfg
    resamples_by_mask = True

    def __init__(self, cfg: UniformPose2dCommandCfg, env: ManagerBasedRLEnv):
        super().__init__(cfg, env)
        if cfg.asset_name not in env.scene:
            raise ValueError(f"asset_name '{cfg.asset_name}' is not in the scene; entities: {env.scene.keys()}")
        self.robot = env.scene[cfg.asset_name]
        n, dev = self.num_envs, self.device
        self.pos_command_w = torch.zeros(n, 3, device=dev)
        self.heading_command_w = torch.zeros(n, device=dev)
        self.pos_command_b = torch.zeros_like(self.pos_command_w)
        self.heading_command_b = torch.zeros_like(self.heading_command_w)
        self._command = torch.zeros(n, 4, device=dev)
        self.metrics["error_pos_2d"] = torch.zeros(n, device=dev)
        self.metrics["error_heading"] = torch.zeros(n, device=dev)

    def __str__(self) -> str:
        return f"UniformPose2dCommand: resampling every {self.cfg.resampling_time_range} s"

    @property
    def command(self) -> torch.Tensor:
        """(num_envs, 4): the goal's position and heading in the base's yaw frame."""
        return self._command

    def _update_metrics(self) -> None:
        data = self.robot.data
        # in place: a captured step's metrics stay the tensors the manager holds
        torch.norm(self.pos_command_w[:, :2] - data.root_pos_w[:, :2], dim=1, out=self.metrics["error_pos_2d"])
        torch.abs(math_utils.wrap_to_pi(self.heading_command_w - data.heading_w), out=self.metrics["error_heading"])

    def _resample_command(self, env_ids: torch.Tensor) -> None:
        """New goals where the (num_envs,) mask ``env_ids`` is set (draws for every env)."""
        r, n, dev, data = self.cfg.ranges, self.num_envs, self.device, self.robot.data
        pos = self._env.scene.env_origins.clone()
        pos[:, 0] += torch.empty(n, device=dev).uniform_(*r.pos_x)
        pos[:, 1] += torch.empty(n, device=dev).uniform_(*r.pos_y)
        pos[:, 2] += data.default_root_state[:, 2]
        if self.cfg.simple_heading:
            to_goal = pos - data.root_pos_w
            facing = torch.atan2(to_goal[:, 1], to_goal[:, 0])
            backing = math_utils.wrap_to_pi(facing + torch.pi)
            facing_closer = (
                math_utils.wrap_to_pi(facing - data.heading_w).abs()
                < math_utils.wrap_to_pi(backing - data.heading_w).abs()
            )
            heading = torch.where(facing_closer, facing, backing)
        else:
            heading = torch.empty(n, device=dev).uniform_(*r.heading)
        masked_copy_(self.pos_command_w, env_ids, pos)
        masked_copy_(self.heading_command_w, env_ids, heading)

    def _update_command(self) -> None:
        data = self.robot.data
        to_goal = self.pos_command_w - data.root_pos_w[:, :3]
        self.pos_command_b[:] = math_utils.quat_apply_inverse(math_utils.yaw_quat(data.root_quat_w), to_goal)
        self.heading_command_b[:] = math_utils.wrap_to_pi(self.heading_command_w - data.heading_w)
        self._command[:, :3] = self.pos_command_b
        self._command[:, 3] = self.heading_command_b

    # -- debug visualization: the goal pose as an arrow along its heading ---------------------------

    def _set_debug_vis_impl(self, debug_vis: bool) -> None:
        if debug_vis and not hasattr(self, "goal_pose_visualizer"):
            self.goal_pose_visualizer = VisualizationMarkers(self.cfg.goal_pose_visualizer_cfg)
        if hasattr(self, "goal_pose_visualizer"):
            self.goal_pose_visualizer.set_visibility(debug_vis)

    def _debug_vis_callback(self, event) -> None:
        if not self.robot.is_initialized:
            return
        zeros = torch.zeros_like(self.heading_command_w)
        quat = math_utils.quat_from_euler_xyz(zeros, zeros, self.heading_command_w)
        self.goal_pose_visualizer.visualize(self.pos_command_w, quat)
