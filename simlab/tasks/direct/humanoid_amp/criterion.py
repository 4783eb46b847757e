"""The AMP humanoids' criterion: forward speed >= 50 % of the clip's, joint RMS error to the nearest clip
frame <= 25 % of the standing pose's, <= 1 fall per env-minute (their env reward is a constant)."""

from __future__ import annotations

import torch

from simlab.tasks.utils.criteria import Criterion


class GaitRecorder:
    """An ``on_step`` hook: the played AMP humanoid against its clip (the AMP tasks' criterion).

    AMP imitates a style, not a clock, so each played pose is compared with the clip pose nearest to
    it; the standing zero pose's error is kept for scale. Steps less than ``settle_seconds`` into an
    episode are not counted (reference-state starts are the clip itself)."""

    def __init__(self, settle_seconds: float):
        self.settle_seconds = settle_seconds
        self.squared_errors: list[torch.Tensor] = []
        self.forward: list[torch.Tensor] = []
        self.horizontal: list[torch.Tensor] = []
        self.falls = 0
        self.env_steps = 0
        self.step_dt = float("nan")
        self.clip_speed = float("nan")
        self.zero_pose_rms = float("nan")
        self._ready = False

    def _setup(self, env) -> None:
        self._ready = True
        self.clip_speed = env.clip_forward_speed
        zero_pose = torch.zeros(1, env.clip_joint_pos.shape[1], device=env.clip_joint_pos.device)
        self.zero_pose_rms = float(env.clip_pose_squared_error(zero_pose).sqrt())
        self.step_dt = env.step_dt

    def __call__(self, env, obs, actions) -> None:
        if not self._ready:
            self._setup(env)
        self.env_steps += env.num_envs
        self.falls += int(env.reset_terminated.sum())
        settled = env.episode_length_buf * env.step_dt >= self.settle_seconds
        if not bool(settled.any()):
            return
        data = env.robot.data
        self.squared_errors.append(env.clip_pose_squared_error(data.joint_pos[settled]).cpu())
        velocity = data.root_lin_vel_w[settled]
        self.forward.append(velocity[:, 0].cpu())
        self.horizontal.append(velocity[:, :2].norm(dim=-1).cpu())

    def summary(self) -> dict[str, float]:
        def mean(chunks: list[torch.Tensor]) -> float:
            return float(torch.cat(chunks).mean()) if chunks else float("nan")

        return {
            "joint_rms_error_rad": mean(self.squared_errors) ** 0.5,
            "zero_pose_joint_rms_error_rad": self.zero_pose_rms,
            "forward_speed_m_s": mean(self.forward),
            "horizontal_speed_m_s": mean(self.horizontal),
            "clip_forward_speed_m_s": self.clip_speed,
            "falls_per_env_minute": self.falls / max(1, self.env_steps) * 60.0 / self.step_dt,
        }


def imitates_clip(
    min_speed_fraction: float = 0.5, max_error_fraction: float = 0.25, max_falls_per_minute: float = 1.0
) -> Criterion:
    """AMP: moves forward at a good part of the clip's speed, in the clip's poses, without falling."""

    def make_hook() -> tuple[GaitRecorder, GaitRecorder]:
        recorder = GaitRecorder(settle_seconds=0.5)
        return recorder, recorder

    def judge(result: dict[str, float], recorder: GaitRecorder) -> tuple[float, bool]:
        gait = recorder.summary()
        speed = gait["forward_speed_m_s"] / max(gait["clip_forward_speed_m_s"], 1e-6)
        posed = gait["joint_rms_error_rad"] <= max_error_fraction * gait["zero_pose_joint_rms_error_rad"]
        return speed, speed >= min_speed_fraction and posed and gait["falls_per_env_minute"] <= max_falls_per_minute

    return Criterion(
        f"forward speed >= {min_speed_fraction:.0%} of the clip's, joint RMS error to the nearest clip frame"
        f" <= {max_error_fraction:.0%} of the standing pose's, <= {max_falls_per_minute:g} fall per env-minute"
        " (score: speed over the clip's)",
        make_hook,
        judge,
    )
