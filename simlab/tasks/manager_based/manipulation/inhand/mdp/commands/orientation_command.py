"""The goal orientation of the in-hand task (Isaac Lab's ``InHandReOrientationCommand``).

The command is the object's goal pose in the env frame: its default position (plus an offset) and a
random orientation, a rotation about x then one about y, each uniform in [-pi, pi]. A goal is redrawn
only when reached (orientation error under the threshold), never on a timer. The metric
``consecutive_success`` counts the goals reached in the episode; the count of each episode that ends is
kept in ``episode_successes`` (for ``simlab bench solve``). Goals are drawn for every env and kept where
a mask is set, so the step can replay as one CUDA graph.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import CommandTerm
from simlab.markers import VisualizationMarkers
from simlab.tasks.direct.inhand_manipulation.inhand_manipulation_env import random_orientation
from simlab.utils import math as math_utils
from simlab.utils.env_mask import env_mask, masked_copy_

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv

    from .commands_cfg import InHandReOrientationCommandCfg


class InHandReOrientationCommand(CommandTerm):
    cfg: InHandReOrientationCommandCfg
    resamples_by_mask = True

    def __init__(self, cfg: InHandReOrientationCommandCfg, env: ManagerBasedRLEnv):
        super().__init__(cfg, env)
        self.object = env.scene[cfg.asset_name]
        n, device = self.num_envs, self.device
        offset = torch.tensor(cfg.init_pos_offset, dtype=torch.float32, device=device)
        self.pos_command_e = self.object.data.default_root_state[:, :3] + offset
        self.pos_command_w = self.pos_command_e + env.scene.env_origins
        self.quat_command_w = torch.zeros(n, 4, device=device)
        self.quat_command_w[:, 0] = 1.0
        self._command = torch.zeros(n, 7, device=device)
        self.goal_version = 0
        """Counts the goal redraws (host side, as ``PhysicsBackend.state_version``): what terms that
        compute from the goal may cache by."""
        self.metrics["orientation_error"] = torch.zeros(n, device=device)
        self.metrics["position_error"] = torch.zeros(n, device=device)
        self.metrics["consecutive_success"] = torch.zeros(n, device=device)
        self.episode_successes = torch.zeros(n, device=device)
        """Goals reached in each env's last finished episode."""

    def __str__(self) -> str:
        return f"InHandReOrientationCommand:\n\tCommand dimension: {tuple(self.command.shape[1:])}\n"

    @property
    def command(self) -> torch.Tensor:
        """The goal pose in the env frame, (num_envs, 7): position and quaternion (w, x, y, z)."""
        return torch.cat((self.pos_command_e, self.quat_command_w), dim=-1, out=self._command)

    def reset(self, env_ids=None) -> dict:
        mask = env_mask(env_ids, self.num_envs, self.device)
        masked_copy_(self.episode_successes, mask, self.metrics["consecutive_success"])
        return super().reset(mask)

    def _update_metrics(self) -> None:
        error = math_utils.quat_error_magnitude(self.object.data.root_quat_w, self.quat_command_w)
        self.metrics["orientation_error"].copy_(error)
        self.metrics["position_error"].copy_(torch.linalg.norm(self.object.data.root_pos_w - self.pos_command_w, dim=1))
        self.metrics["consecutive_success"] += (error < self.cfg.orientation_success_threshold).float()

    def _resample_command(self, env_ids: torch.Tensor) -> None:
        """New goal orientations where the (num_envs,) mask ``env_ids`` is set."""
        rand = 2.0 * torch.rand((self.num_envs, 2), device=self.device) - 1.0
        quat = random_orientation(rand)  # about x by rand[:, 0] * pi, then about y by rand[:, 1] * pi
        self.goal_version += 1
        if self.cfg.make_quat_unique:
            quat = math_utils.quat_unique(quat)
        masked_copy_(self.quat_command_w, env_ids, quat)

    def _update_command(self) -> None:
        if self.cfg.update_goal_on_success:
            self._resample(self.metrics["orientation_error"] < self.cfg.orientation_success_threshold)

    def _set_debug_vis_impl(self, debug_vis: bool) -> None:
        if debug_vis:
            if not hasattr(self, "goal_pose_visualizer"):
                self.goal_pose_visualizer = VisualizationMarkers(self.cfg.goal_pose_visualizer_cfg)
            self.goal_pose_visualizer.set_visibility(True)
        elif hasattr(self, "goal_pose_visualizer"):
            self.goal_pose_visualizer.set_visibility(False)

    def _debug_vis_callback(self, event) -> None:
        offset = torch.tensor(self.cfg.marker_pos_offset, device=self.device)
        self.goal_pose_visualizer.visualize(translations=self.pos_command_w + offset, orientations=self.quat_command_w)
