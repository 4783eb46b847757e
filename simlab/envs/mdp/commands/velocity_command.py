"""Base velocity commands ``(v_x, v_y, w_z)`` in the robot's root frame, optionally steering the
yaw rate towards a sampled heading."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils
from simlab.managers.command_manager import CommandTerm
from simlab.markers import VisualizationMarkers
from simlab.utils.env_mask import masked_copy_

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

    from .commands_cfg import UniformVelocityCommandCfg


class UniformVelocityCommand(CommandTerm):
    """Velocities drawn uniformly from ``cfg.ranges``. A fraction ``rel_standing_envs`` of the envs
    is told to stand still; with ``heading_command``, a fraction ``rel_heading_envs`` gets its yaw
    rate from a heading error: ``w_z = clip(heading_control_stiffness * wrap(heading - yaw))``."""

    cfg: UniformVelocityCommandCfg
    resamples_by_mask = True

    def __init__(self, cfg: UniformVelocityCommandCfg, env: ManagerBasedRLEnv):
        super().__init__(cfg, env)
        if cfg.heading_command and cfg.ranges.heading is None:
            raise ValueError("heading_command=True needs ranges.heading=(min, max) radians")
        if cfg.asset_name not in env.scene:
            raise ValueError(f"asset_name '{cfg.asset_name}' is not in the scene; entities: {env.scene.keys()}")
        self.robot = env.scene[cfg.asset_name]
        n, dev = self.num_envs, self.device
        self.vel_command_b = torch.zeros(n, 3, device=dev)
        self.heading_target = torch.zeros(n, device=dev)
        self.is_heading_env = torch.zeros(n, dtype=torch.bool, device=dev)
        self.is_standing_env = torch.zeros(n, dtype=torch.bool, device=dev)
        self.metrics["error_vel_xy"] = torch.zeros(n, device=dev)
        self.metrics["error_vel_yaw"] = torch.zeros(n, device=dev)

    def __str__(self) -> str:
        return (
            f"UniformVelocityCommand: resampling every {self.cfg.resampling_time_range} s,"
            f" heading command {self.cfg.heading_command}, standing envs {self.cfg.rel_standing_envs}"
        )

    @property
    def command(self) -> torch.Tensor:
        """(num_envs, 3) desired ``(v_x, v_y, w_z)`` in the root frame."""
        return self.vel_command_b

    def _update_metrics(self) -> None:
        steps = self.cfg.resampling_time_range[1] / self._env.step_dt
        data = self.robot.data
        self.metrics["error_vel_xy"] += (
            torch.norm(self.vel_command_b[:, :2] - data.root_lin_vel_b[:, :2], dim=-1) / steps
        )
        self.metrics["error_vel_yaw"] += torch.abs(self.vel_command_b[:, 2] - data.root_ang_vel_b[:, 2]) / steps

    def _resample_command(self, env_ids: torch.Tensor) -> None:
        """New commands where the (num_envs,) mask ``env_ids`` is set (draws for all envs)."""
        r, mask = self.cfg.ranges, env_ids
        # one draw for every env and quantity (each op is a kernel launch on the GPU): columns
        # v_x, v_y, w_z, heading, then two uniform [0, 1) numbers for the heading and standing envs
        bounds = (r.lin_vel_x, r.lin_vel_y, r.ang_vel_z, r.heading or (0.0, 0.0), (0.0, 1.0), (0.0, 1.0))
        if getattr(self, "_draw_bounds", None) != bounds:  # first call, or a curriculum changed the ranges
            low_width = torch.tensor([[lo, hi - lo] for lo, hi in bounds], device=self.device)
            if hasattr(self, "_draw_low"):  # in place: a captured step reads these tensors
                self._draw_low.copy_(low_width[:, 0])
                self._draw_width.copy_(low_width[:, 1])
            else:
                self._draw_low, self._draw_width = low_width[:, 0].clone(), low_width[:, 1].clone()
            self._draw_bounds = bounds
        draws = torch.rand(self.num_envs, 6, device=self.device).mul_(self._draw_width).add_(self._draw_low)
        masked_copy_(self.vel_command_b, mask, draws[:, :3])
        if self.cfg.heading_command:
            masked_copy_(self.heading_target, mask, draws[:, 3])
            masked_copy_(self.is_heading_env, mask, draws[:, 4] <= self.cfg.rel_heading_envs)
        masked_copy_(self.is_standing_env, mask, draws[:, 5] <= self.cfg.rel_standing_envs)

    def _update_command(self) -> None:
        if self.cfg.heading_command:
            error = math_utils.wrap_to_pi(self.heading_target - self.robot.data.heading_w)
            yaw_rate = (self.cfg.heading_control_stiffness * error).clip(*self.cfg.ranges.ang_vel_z)
            self.vel_command_b[:, 2] = torch.where(self.is_heading_env, yaw_rate, self.vel_command_b[:, 2])
        self.vel_command_b.masked_fill_(self.is_standing_env[:, None], 0.0)

    # -- debug visualization: arrows of the commanded (green) and current (blue) planar velocity ----

    def _set_debug_vis_impl(self, debug_vis: bool) -> None:
        if debug_vis and not hasattr(self, "goal_vel_visualizer"):
            self.goal_vel_visualizer = VisualizationMarkers(self.cfg.goal_vel_visualizer_cfg)
            self.current_vel_visualizer = VisualizationMarkers(self.cfg.current_vel_visualizer_cfg)
        if hasattr(self, "goal_vel_visualizer"):
            self.goal_vel_visualizer.set_visibility(debug_vis)
            self.current_vel_visualizer.set_visibility(debug_vis)

    def _debug_vis_callback(self, event) -> None:
        if not self.robot.is_initialized:
            return
        above_base = self.robot.data.root_pos_w.clone()
        above_base[:, 2] += 0.5
        goal_scale, goal_quat = self._arrow_of(self.command[:, :2])
        current_scale, current_quat = self._arrow_of(self.robot.data.root_lin_vel_b[:, :2])
        self.goal_vel_visualizer.visualize(above_base, goal_quat, goal_scale)
        self.current_vel_visualizer.visualize(above_base, current_quat, current_scale)

    def _arrow_of(self, xy_velocity_b: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """Scales and world orientations of arrows pointing along root-frame planar velocities,
        1.5 m long per m/s."""
        scale = torch.ones(self.num_envs, 3, device=self.device)
        scale[:, 0] = torch.linalg.norm(xy_velocity_b, dim=1) * 1.5
        zeros = torch.zeros(self.num_envs, device=self.device)
        heading_b = torch.atan2(xy_velocity_b[:, 1], xy_velocity_b[:, 0])
        quat_b = math_utils.quat_from_euler_xyz(zeros, zeros, heading_b)
        return scale, math_utils.quat_mul(self.robot.data.root_quat_w, quat_b)
