"""Pose commands for a body of the robot: positions and orientations drawn uniformly in the robot's
root frame (Isaac Lab's ``UniformPoseCommand``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils
from simlab.managers.command_manager import CommandTerm
from simlab.markers import VisualizationMarkers
from simlab.utils.env_mask import masked_copy_

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

    from .commands_cfg import UniformPoseCommandCfg


class UniformPoseCommand(CommandTerm):
    """``(x, y, z, qw, qx, qy, qz)`` in the root frame of ``asset_name``, for its body ``body_name``.

    Metrics: ``position_error`` (m) and ``orientation_error`` (rad) of the body to the command.
    """

    cfg: UniformPoseCommandCfg
    resamples_by_mask = True

    def __init__(self, cfg: UniformPoseCommandCfg, env: ManagerBasedRLEnv):
        super().__init__(cfg, env)
        if cfg.asset_name not in env.scene:
            raise ValueError(f"asset_name '{cfg.asset_name}' is not in the scene; entities: {env.scene.keys()}")
        self.robot = env.scene[cfg.asset_name]
        self.body_idx = self.robot.find_bodies(cfg.body_name)[0][0]
        n, dev = self.num_envs, self.device
        self.pose_command_b = torch.zeros(n, 7, device=dev)
        self.pose_command_b[:, 3] = 1.0
        self.pose_command_w = torch.zeros_like(self.pose_command_b)
        self.metrics["position_error"] = torch.zeros(n, device=dev)
        self.metrics["orientation_error"] = torch.zeros(n, device=dev)

    def __str__(self) -> str:
        return f"UniformPoseCommand: body '{self.cfg.body_name}', resampling every {self.cfg.resampling_time_range} s"

    @property
    def command(self) -> torch.Tensor:
        """(num_envs, 7) desired pose of the body in the root frame."""
        return self.pose_command_b

    def _update_metrics(self) -> None:
        data = self.robot.data
        pos_w, quat_w = math_utils.combine_frame_transforms(
            data.root_pos_w, data.root_quat_w, self.pose_command_b[:, :3], self.pose_command_b[:, 3:]
        )
        self.pose_command_w[:, :3], self.pose_command_w[:, 3:] = pos_w, quat_w
        pos_err, rot_err = math_utils.compute_pose_error(
            pos_w, quat_w, data.body_pos_w[:, self.body_idx], data.body_quat_w[:, self.body_idx]
        )
        # in place: a captured step's metrics stay the tensors the manager holds
        torch.norm(pos_err, dim=-1, out=self.metrics["position_error"])
        torch.norm(rot_err, dim=-1, out=self.metrics["orientation_error"])

    def _resample_command(self, env_ids: torch.Tensor) -> None:
        """New poses where the (num_envs,) mask ``env_ids`` is set (draws for every env)."""
        r, n, dev = self.cfg.ranges, self.num_envs, self.device

        def draw(bounds: tuple[float, float]) -> torch.Tensor:
            return torch.empty(n, device=dev).uniform_(*bounds)

        pos = torch.stack([draw(r.pos_x), draw(r.pos_y), draw(r.pos_z)], dim=-1)
        quat = math_utils.quat_from_euler_xyz(draw(r.roll), draw(r.pitch), draw(r.yaw))
        if self.cfg.make_quat_unique:
            quat = math_utils.quat_unique(quat)
        masked_copy_(self.pose_command_b, env_ids, torch.cat([pos, quat], dim=-1))

    def _update_command(self) -> None:
        pass

    # -- debug visualization: the commanded frame and the body's frame ----------------------------

    def _set_debug_vis_impl(self, debug_vis: bool) -> None:
        if debug_vis and not hasattr(self, "goal_pose_visualizer"):
            self.goal_pose_visualizer = VisualizationMarkers(self.cfg.goal_pose_visualizer_cfg)
            self.current_pose_visualizer = VisualizationMarkers(self.cfg.current_pose_visualizer_cfg)
        if hasattr(self, "goal_pose_visualizer"):
            self.goal_pose_visualizer.set_visibility(debug_vis)
            self.current_pose_visualizer.set_visibility(debug_vis)

    def _debug_vis_callback(self, event) -> None:
        if not self.robot.is_initialized:
            return
        self.goal_pose_visualizer.visualize(self.pose_command_w[:, :3], self.pose_command_w[:, 3:])
        body_pose = self.robot.data.body_pose_w[:, self.body_idx]
        self.current_pose_visualizer.visualize(body_pose[:, :3], body_pose[:, 3:])
