"""The motion command: where in its clip each env is, the clip's target states, and the resets that
start an env at a clip time drawn where the policy fails most (adaptive sampling)."""

from __future__ import annotations

import math
from dataclasses import MISSING, field
from typing import TYPE_CHECKING

import torch

import simlab.utils.math as math_utils
from simlab.managers import CommandTerm, CommandTermCfg
from simlab.utils import configclass
from simlab.utils.env_mask import masked_copy_
from simlab.utils.errors import ConfigError

from ..motion_clip import MotionClip

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv


class MotionCommand(CommandTerm):
    """Plays ``cfg.motion_file`` for every env from its own clip time; the command (what the policy
    sees) is the clip's joint positions and velocities at that time.

    Body targets are compared in the robot's own frame: ``body_pos_relative_w`` and
    ``body_quat_relative_w`` are the clip's bodies moved so that the clip's anchor sits on the
    robot's anchor (its horizontal position and heading; the clip's height), so that a policy that
    drifts is judged by its posture, and the anchor rewards judge the drift.

    A finished clip, or a reset, restarts the env at a time drawn over one-second bins of the clip:
    in proportion to a running average of the failures in each bin, plus a uniform share.
    """

    cfg: MotionCommandCfg
    resamples_by_mask = True  # draws for every env, keeps the draws where the mask is set

    def __init__(self, cfg: MotionCommandCfg, env: ManagerBasedRLEnv):
        super().__init__(cfg, env)
        self.robot = env.scene[cfg.asset_name]
        # a clip stored without body states gets them by forward kinematics of the robot's model file
        clip = MotionClip.load(cfg.motion_file, mjcf=getattr(self.robot.cfg.spawn, "asset_path", None))
        if abs(clip.fps * env.step_dt - 1.0) > 1e-3:
            raise ConfigError(
                f"{cfg.motion_file}: the clip runs at {clip.fps:g} fps but the env steps at {1 / env.step_dt:g} Hz;"
                f" convert it at the env's rate (scripts/tools/csv_to_npz.py --output_fps {1 / env.step_dt:g},"
                " or clip_from_csv(..., output_fps=...))."
            )
        missing = sorted(set(self.robot.joint_names) - set(clip.joint_names))
        if missing:
            raise ConfigError(f"{cfg.motion_file}: the clip has no column for the robot's joints {missing}.")
        unknown = sorted(set(cfg.body_names) - set(clip.body_names))
        if unknown:
            raise ConfigError(f"{cfg.motion_file}: the clip has no body {unknown}; it has {clip.body_names}.")
        if cfg.anchor_body_name not in cfg.body_names:
            raise ConfigError(f"anchor_body_name '{cfg.anchor_body_name}' must be one of body_names {cfg.body_names}.")
        dev = self.device
        columns = [clip.joint_names.index(name) for name in self.robot.joint_names]  # the robot's joint order
        bodies = [clip.body_names.index(name) for name in cfg.body_names]
        self.clip_joint_pos = torch.tensor(clip.joint_pos[:, columns], device=dev)
        self.clip_joint_vel = torch.tensor(clip.joint_vel[:, columns], device=dev)
        self.clip_body_pos_w = torch.tensor(clip.body_pos_w[:, bodies], device=dev)
        self.clip_body_quat_w = torch.tensor(clip.body_quat_w[:, bodies], device=dev)
        self.clip_body_lin_vel_w = torch.tensor(clip.body_lin_vel_w[:, bodies], device=dev)
        self.clip_body_ang_vel_w = torch.tensor(clip.body_ang_vel_w[:, bodies], device=dev)
        self.num_frames = clip.num_frames
        self.robot_body_ids = torch.tensor(self.robot.find_bodies(cfg.body_names, preserve_order=True)[0], device=dev)
        self.anchor = cfg.body_names.index(cfg.anchor_body_name)
        self._pose_bounds = _bounds(cfg.pose_range, dev)  # on the device once: no host copy per step
        self._velocity_bounds = _bounds(cfg.velocity_range, dev)
        self.robot_anchor = self.robot.body_names.index(cfg.anchor_body_name)

        self.time_steps = torch.zeros(self.num_envs, dtype=torch.long, device=dev)
        self.body_pos_relative_w = torch.zeros(self.num_envs, len(bodies), 3, device=dev)
        self.body_quat_relative_w = torch.zeros(self.num_envs, len(bodies), 4, device=dev)
        self.body_quat_relative_w[..., 0] = 1.0
        # adaptive sampling over one-second bins
        self.bin_count = int(self.num_frames // round(1.0 / env.step_dt)) + 1
        self.bin_failed = torch.zeros(self.bin_count, device=dev)
        self._bin_failed_now = torch.zeros(self.bin_count, device=dev)
        for name in ("error_anchor_pos", "error_anchor_rot", "error_body_pos", "error_body_rot", "error_joint_pos"):
            self.metrics[name] = torch.zeros(self.num_envs, device=dev)

    # -- the clip at each env's time --------------------------------------------------------------

    @property
    def command(self) -> torch.Tensor:
        return torch.cat([self.joint_pos, self.joint_vel], dim=1)

    @property
    def joint_pos(self) -> torch.Tensor:
        return self.clip_joint_pos[self.time_steps]

    @property
    def joint_vel(self) -> torch.Tensor:
        return self.clip_joint_vel[self.time_steps]

    @property
    def body_pos_w(self) -> torch.Tensor:
        return self.clip_body_pos_w[self.time_steps] + self._env.scene.env_origins[:, None]

    @property
    def body_quat_w(self) -> torch.Tensor:
        return self.clip_body_quat_w[self.time_steps]

    @property
    def body_lin_vel_w(self) -> torch.Tensor:
        return self.clip_body_lin_vel_w[self.time_steps]

    @property
    def body_ang_vel_w(self) -> torch.Tensor:
        return self.clip_body_ang_vel_w[self.time_steps]

    @property
    def anchor_pos_w(self) -> torch.Tensor:
        return self.body_pos_w[:, self.anchor]

    @property
    def anchor_quat_w(self) -> torch.Tensor:
        return self.body_quat_w[:, self.anchor]

    # -- the robot's matching bodies --------------------------------------------------------------

    @property
    def robot_body_pos_w(self) -> torch.Tensor:
        return self.robot.data.body_pos_w[:, self.robot_body_ids]

    @property
    def robot_body_quat_w(self) -> torch.Tensor:
        return self.robot.data.body_quat_w[:, self.robot_body_ids]

    @property
    def robot_body_lin_vel_w(self) -> torch.Tensor:
        return self.robot.data.body_lin_vel_w[:, self.robot_body_ids]

    @property
    def robot_body_ang_vel_w(self) -> torch.Tensor:
        return self.robot.data.body_ang_vel_w[:, self.robot_body_ids]

    @property
    def robot_anchor_pos_w(self) -> torch.Tensor:
        return self.robot.data.body_pos_w[:, self.robot_anchor]

    @property
    def robot_anchor_quat_w(self) -> torch.Tensor:
        return self.robot.data.body_quat_w[:, self.robot_anchor]

    # -- CommandTerm ------------------------------------------------------------------------------

    def _update_metrics(self) -> None:
        self.metrics["error_anchor_pos"].copy_(torch.norm(self.anchor_pos_w - self.robot_anchor_pos_w, dim=-1))
        self.metrics["error_anchor_rot"].copy_(
            math_utils.quat_error_magnitude(self.anchor_quat_w, self.robot_anchor_quat_w)
        )
        self.metrics["error_body_pos"].copy_(
            torch.norm(self.body_pos_relative_w - self.robot_body_pos_w, dim=-1).mean(-1)
        )
        self.metrics["error_body_rot"].copy_(
            math_utils.quat_error_magnitude(self.body_quat_relative_w, self.robot_body_quat_w).mean(-1)
        )
        self.metrics["error_joint_pos"].copy_(torch.norm(self.joint_pos - self.robot.data.joint_pos, dim=-1))

    def _start_probabilities(self) -> torch.Tensor:
        weights = self.bin_failed + self.cfg.adaptive_uniform_ratio / self.bin_count
        return weights / weights.sum()

    def _sample_times(self, mask: torch.Tensor) -> None:
        """New clip times where ``mask`` is set (every env draws; fixed shapes, no host reads)."""
        if not self.cfg.adaptive_sampling:
            masked_copy_(self.time_steps, mask, 0)
            return
        failed = self._env.termination_manager.terminated & mask
        bins = ((self.time_steps * self.bin_count) // self.num_frames).clamp(max=self.bin_count - 1)
        self._bin_failed_now.scatter_add_(0, bins, failed.float())
        # inverse-CDF draw of a bin, then a uniform time inside it
        cdf = torch.cumsum(self._start_probabilities(), 0)
        drawn = torch.searchsorted(cdf, torch.rand(self.num_envs, device=self.device) * cdf[-1]).clamp(
            max=self.bin_count - 1
        )
        start = (drawn + torch.rand(self.num_envs, device=self.device)) / self.bin_count
        masked_copy_(self.time_steps, mask, (start * (self.num_frames - 1)).long())

    def _resample_command(self, mask: torch.Tensor) -> None:
        """Start the envs where ``mask`` is set at clip times, in the clip's state there, slightly perturbed."""
        self._sample_times(mask)
        n, steps, origins = self.num_envs, self.time_steps, self._env.scene.env_origins
        pose = _uniform(self._pose_bounds, n)
        root_pos = self.clip_body_pos_w[steps, 0] + origins + pose[:, :3]
        delta = math_utils.quat_from_euler_xyz(pose[:, 3], pose[:, 4], pose[:, 5])
        root_quat = math_utils.quat_mul(delta, self.clip_body_quat_w[steps, 0])
        velocity = _uniform(self._velocity_bounds, n)
        root_lin_vel = self.clip_body_lin_vel_w[steps, 0] + velocity[:, :3]
        root_ang_vel = self.clip_body_ang_vel_w[steps, 0] + velocity[:, 3:]
        low, high = self.cfg.joint_position_range
        joint_pos = self.clip_joint_pos[steps] + torch.empty_like(self.clip_joint_pos[steps]).uniform_(low, high)
        limits = self.robot.data.soft_joint_pos_limits
        joint_pos = joint_pos.clamp(limits[..., 0], limits[..., 1])
        self.robot.write_root_state_to_sim(
            torch.cat([root_pos, root_quat, root_lin_vel, root_ang_vel], -1), env_ids=mask
        )
        self.robot.write_joint_state_to_sim(joint_pos, self.clip_joint_vel[steps], env_ids=mask)
        # until the next update moves them onto the robot, the targets are the clip's own (where the robot starts)
        masked_copy_(self.body_pos_relative_w, mask, self.clip_body_pos_w[steps] + origins[:, None])
        masked_copy_(self.body_quat_relative_w, mask, self.clip_body_quat_w[steps])

    def _update_command(self) -> None:
        self.time_steps += 1
        self._resample_command(self.time_steps >= self.num_frames)
        # the clip's bodies, moved onto the robot's anchor (horizontal position and heading)
        anchor_pos = self.anchor_pos_w[:, None]
        anchor_quat = self.anchor_quat_w[:, None].expand_as(self.body_quat_relative_w)
        robot_pos = self.robot_anchor_pos_w[:, None].clone()
        robot_pos[..., 2] = anchor_pos[..., 2]
        robot_quat = self.robot_anchor_quat_w[:, None].expand_as(anchor_quat)
        delta = math_utils.yaw_quat(math_utils.quat_mul(robot_quat, math_utils.quat_inv(anchor_quat)))
        self.body_quat_relative_w.copy_(math_utils.quat_mul(delta, self.body_quat_w))
        self.body_pos_relative_w.copy_(robot_pos + math_utils.quat_apply(delta, self.body_pos_w - anchor_pos))
        # failures counted this step enter the bins' running average
        alpha = self.cfg.adaptive_alpha
        self.bin_failed.mul_(1 - alpha).add_(alpha * self._bin_failed_now)
        self._bin_failed_now.zero_()

    def sampling_entropy(self) -> float:
        """Normalized entropy of the start-time distribution (1: uniform)."""
        p = self._start_probabilities()
        return float(-(p * (p + 1e-12).log()).sum() / math.log(max(self.bin_count, 2)))


def _bounds(ranges: dict[str, tuple[float, float]], device) -> torch.Tensor:
    """(6, 2) low and high of x, y, z, roll, pitch, yaw (0 where ``ranges`` has no entry)."""
    return torch.tensor([ranges.get(k, (0.0, 0.0)) for k in ("x", "y", "z", "roll", "pitch", "yaw")], device=device)


def _uniform(bounds: torch.Tensor, n: int) -> torch.Tensor:
    return bounds[:, 0] + torch.rand(n, 6, device=bounds.device) * (bounds[:, 1] - bounds[:, 0])


@configclass
class MotionCommandCfg(CommandTermCfg):
    class_type: type = MotionCommand
    resampling_time_range: tuple[float, float] = (1.0e9, 1.0e9)  # the clip's end resamples, not a timer
    asset_name: str = "robot"
    motion_file: str = MISSING
    """A clip in the npz format of ``simlab.tasks.manager_based.tracking.motion_clip``, at the env's rate: its
    path, or a shipped clip's name (``g1_walk``)."""
    anchor_body_name: str = MISSING
    body_names: list[str] = MISSING
    pose_range: dict[str, tuple[float, float]] = field(default_factory=dict)
    velocity_range: dict[str, tuple[float, float]] = field(default_factory=dict)
    joint_position_range: tuple[float, float] = (-0.1, 0.1)
    adaptive_sampling: bool = True
    adaptive_uniform_ratio: float = 0.1
    """Share of start times drawn uniformly over the clip."""
    adaptive_alpha: float = 0.001
    """Weight of each step's failures in the bins' running average."""
