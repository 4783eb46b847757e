"""When is a task solved? Each criterion plays a policy and says whether what it saw passes.

cartpole: |pole angle| < 0.2 rad in >= 95 % of the env-steps of 64 envs over 5 s.
humanoid, ant (direct and manager-based): the torso's mean speed towards the target (+x, where the
tasks' target lies 1 km away) over the played window of 64 envs for 5 s, falls and resets included,
is at least a stated speed. A speed, not a reward: the manager-based tasks' rewards are scaled by the
step time and the direct ones' are not, so one reward threshold cannot serve both.
velocity tasks (Go2, Anymal): the base's planar velocity follows the command, mean error <= 0.25 m/s.
quadcopter: from 2 s into an episode (the flight to the goal), within 0.3 m of it in >= 75 % of the env-steps.
cart double pendulum: pole and pendulum both within 0.2 rad of upright in >= 75 % of the env-steps
(episodes start up to 0.79 rad off, so the first moments of each are spent swinging them up).
Franka reach: at the end of each command window, mean position error < 2 cm and mean orientation
error < 0.1 rad (``scripts/benchmarks/manipulation_learn.py``'s criterion).
Franka lift: >= 80 % of the episodes end with the cube within 5 cm of its commanded position.
Franka cabinet (direct and manager-based): >= 80 % of the episodes end with the top drawer open >= 20 cm.
AMP humanoids: forward speed >= 50 % of the clip's, joint RMS error to the nearest clip frame <= 25 % of
the standing pose's, <= 1 fall per env-minute (their env reward is a constant).

Criteria that judge whole episodes or command windows state how long a play must at least last
(``Criterion.min_seconds``); :meth:`Criterion.play_seconds` lengthens a shorter request to it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import Any

import torch

# Mean torso speed towards the target [m/s] a played policy must keep. Measured on the CPU (64 envs,
# 5 s): untrained policies of Ant-v0 and Humanoid-v0 -0.03 and 0.03 m/s; the shipped Ant-Direct-v0
# and Humanoid-Direct-v0 policies 7.4 and 3.0 m/s.
FORWARD_SPEED_THRESHOLDS = {"Humanoid": 1.0, "Ant": 1.0}


def pole_angle_tracker(threshold: float) -> tuple[Callable[[Any, Any, Any], None], dict[str, int]]:
    """An ``on_step`` hook (for :func:`simlab.cli.play.rollout`) counting env-steps with
    |pole angle| below ``threshold``; returns the hook and its counts."""
    counts = {"inside": 0, "total": 0}
    joint: dict = {}

    def on_step(env, obs, actions) -> None:
        if not joint:
            for asset in env.scene.articulations.values():
                if "cart_to_pole" in asset.joint_names:
                    joint["asset"], joint["id"] = asset, asset.joint_names.index("cart_to_pole")
            if not joint:
                raise RuntimeError("No articulation with a 'cart_to_pole' joint in this task.")
        angle = joint["asset"].data.joint_pos[:, joint["id"]]
        angle = torch.remainder(angle + math.pi, 2 * math.pi) - math.pi
        counts["inside"] += int((angle.abs() < threshold).sum())
        counts["total"] += angle.numel()

    return on_step, counts


@dataclass
class Criterion:
    """What a played policy must show; ``judge`` turns a rollout into (score, passed)."""

    description: str
    make_hook: Callable[[], tuple[Callable | None, Any]]
    judge: Callable[[dict[str, float], Any], tuple[float, bool]]
    min_seconds: float = 0.0  # a shorter play sees no finished episode or command window

    def play_seconds(self, requested: float) -> float:
        """How long to play for a verdict: ``requested``, or ``min_seconds`` where that is longer."""
        return max(requested, self.min_seconds)


def pole_upright(threshold: float = 0.2, fraction: float = 0.95) -> Criterion:
    def judge(result: dict[str, float], counts: dict[str, int]) -> tuple[float, bool]:
        inside = counts["inside"] / max(1, counts["total"])
        return inside, inside >= fraction

    return Criterion(
        f"|pole angle| < {threshold} rad in >= {fraction:.0%} of steps",
        lambda: pole_angle_tracker(threshold),
        judge,
    )


def mean_reward_at_least(threshold: float) -> Criterion:
    def judge(result: dict[str, float], _: Any) -> tuple[float, bool]:
        return result["mean_reward"], result["mean_reward"] >= threshold

    return Criterion(f"mean reward per env-step >= {threshold:g}", lambda: (None, None), judge)


def velocity_tracker() -> tuple[Callable[[Any, Any, Any], None], dict[str, float]]:
    """An ``on_step`` hook summing ``|v_xy command - v_xy|`` (base frame) over env-steps."""
    sums = {"error": 0.0, "total": 0}

    def on_step(env, obs, actions) -> None:
        base = env.unwrapped
        command = base.command_manager.get_command("base_velocity")
        velocity = base.scene["robot"].data.root_lin_vel_b
        sums["error"] += float(torch.linalg.norm(command[:, :2] - velocity[:, :2], dim=-1).sum())
        sums["total"] += command.shape[0]

    return on_step, sums


def tracks_velocity(max_error: float = 0.25) -> Criterion:
    def judge(result: dict[str, float], sums: dict[str, float]) -> tuple[float, bool]:
        error = sums["error"] / max(1, sums["total"])
        return error, error <= max_error

    return Criterion(f"mean |v_xy command - v_xy| <= {max_error} m/s", velocity_tracker, judge)


def forward_speed_tracker() -> tuple[Callable[[Any, Any, Any], None], dict[str, float]]:
    """An ``on_step`` hook summing the root's world-frame x velocity (towards the target) over env-steps."""
    sums = {"speed": 0.0, "total": 0}

    def on_step(env, obs, actions) -> None:
        velocity = env.unwrapped.scene["robot"].data.root_lin_vel_w
        sums["speed"] += float(velocity[:, 0].sum())
        sums["total"] += velocity.shape[0]

    return on_step, sums


def runs_forward(min_speed: float) -> Criterion:
    def judge(result: dict[str, float], sums: dict[str, float]) -> tuple[float, bool]:
        speed = sums["speed"] / max(1, sums["total"])
        return speed, sums["total"] > 0 and speed >= min_speed

    return Criterion(f"mean torso speed towards the target >= {min_speed:g} m/s", forward_speed_tracker, judge)


def goal_distance_tracker(
    radius: float, settle_seconds: float
) -> tuple[Callable[[Any, Any, Any], None], dict[str, int]]:
    """An ``on_step`` hook counting env-steps, ``settle_seconds`` or more after the quadcopter's start
    (the play's first step or its last reset: the flight to the goal), within ``radius`` of its goal.

    The time is counted here: the task starts its episodes at random lengths.
    """
    counts = {"inside": 0, "total": 0}
    flying: dict[str, torch.Tensor] = {}

    def on_step(env, obs, actions) -> None:
        base = env.unwrapped
        steps = flying.setdefault("steps", torch.zeros(base.num_envs, dtype=torch.long, device=base.device))
        steps.add_(1)
        settled = steps >= math.ceil(settle_seconds / base.step_dt - 1e-6)
        steps.masked_fill_(base.reset_buf, 0)  # restarted: the next step is its first
        distance = torch.linalg.norm(base._desired_pos_w - base._robot.data.root_pos_w, dim=1)
        counts["inside"] += int((settled & (distance < radius)).sum())
        counts["total"] += int(settled.sum())

    return on_step, counts


def reaches_goal(radius: float = 0.3, fraction: float = 0.75, settle_seconds: float = 2.0) -> Criterion:
    def judge(result: dict[str, float], counts: dict[str, int]) -> tuple[float, bool]:
        inside = counts["inside"] / max(1, counts["total"])
        return inside, counts["total"] > 0 and inside >= fraction

    return Criterion(
        f"from {settle_seconds:g} s into an episode, within {radius} m of the goal in >= {fraction:.0%} of steps",
        lambda: goal_distance_tracker(radius, settle_seconds),
        judge,
    )


def _wrapped(angle: torch.Tensor) -> torch.Tensor:
    return torch.remainder(angle + math.pi, 2 * math.pi) - math.pi


def double_pendulum_tracker(threshold: float) -> tuple[Callable[[Any, Any, Any], None], dict[str, int]]:
    """An ``on_step`` hook counting env-steps with the pole and the pendulum (its angle in the world:
    pole + pendulum joint) both within ``threshold`` of upright."""
    counts = {"inside": 0, "total": 0}

    def on_step(env, obs, actions) -> None:
        robot = env.scene["robot"]  # the scene, not env.robot: training wraps the two agents as one
        pole = robot.data.joint_pos[:, robot.joint_names.index("cart_to_pole")]
        pendulum = pole + robot.data.joint_pos[:, robot.joint_names.index("pole_to_pendulum")]
        upright = (_wrapped(pole).abs() < threshold) & (_wrapped(pendulum).abs() < threshold)
        counts["inside"] += int(upright.sum())
        counts["total"] += upright.numel()

    return on_step, counts


def both_poles_upright(threshold: float = 0.2, fraction: float = 0.75) -> Criterion:
    def judge(result: dict[str, float], counts: dict[str, int]) -> tuple[float, bool]:
        inside = counts["inside"] / max(1, counts["total"])
        return inside, inside >= fraction

    return Criterion(
        f"pole and pendulum both within {threshold} rad of upright in >= {fraction:.0%} of steps",
        lambda: double_pendulum_tracker(threshold),
        judge,
    )


def command_window_tracker() -> tuple[Callable[[Any, Any, Any], None], dict[str, list[torch.Tensor]]]:
    """An ``on_step`` hook keeping the reach task's position [m] and orientation [rad] errors of the
    hand to its ``ee_pose`` command on the last step of every command window."""
    errors: dict[str, list[torch.Tensor]] = {"position": [], "orientation": []}

    def on_step(env, obs, actions) -> None:
        from simlab.managers import SceneEntityCfg
        from simlab.tasks.manager_based.manipulation.reach import mdp

        term = env.command_manager.get_term("ee_pose")
        ending = term.time_left <= env.step_dt * 0.5  # the command changes at the next step
        if not bool(ending.any()):
            return
        hand = SceneEntityCfg("robot", body_names=[term.cfg.body_name])
        hand.resolve(env.scene)
        errors["position"].append(mdp.position_command_error(env, "ee_pose", hand)[ending].cpu())
        errors["orientation"].append(mdp.orientation_command_error(env, "ee_pose", hand)[ending].cpu())

    return on_step, errors


def reaches_pose(position_m: float = 0.02, orientation_rad: float = 0.1, window_s: float = 4.0) -> Criterion:
    """Score: the larger of the mean errors as a fraction of their tolerance (passes at < 1)."""

    def judge(result: dict[str, float], errors: dict[str, list[torch.Tensor]]) -> tuple[float, bool]:
        if not errors["position"]:
            return math.inf, False
        position = float(torch.cat(errors["position"]).mean())
        orientation = float(torch.cat(errors["orientation"]).mean())
        score = max(position / position_m, orientation / orientation_rad)
        return score, score < 1.0

    return Criterion(
        f"at the end of each command window, mean position error < {position_m} m and mean orientation error"
        f" < {orientation_rad} rad (score: the larger error over its tolerance, < 1)",
        command_window_tracker,
        judge,
        min_seconds=window_s + 0.5,
    )


def episode_end_tracker(
    succeeded: Callable[[Any], torch.Tensor],
) -> tuple[Callable[[Any, Any, Any], None], dict[str, int]]:
    """An ``on_step`` hook for manager-based tasks judging each episode on its last step: envs one step
    short of their time limit are judged by ``succeeded(env)`` (a (num_envs,) bool tensor) now, as the
    next step resets them; episodes ended early by a termination count as failed."""
    counts = {"success": 0, "episodes": 0}

    def on_step(env, obs, actions) -> None:
        last = env.episode_length_buf >= env.max_episode_length - 1
        if bool(last.any()):
            counts["success"] += int((succeeded(env) & last).sum())
            counts["episodes"] += int(last.sum())
        counts["episodes"] += int(env.termination_manager.terminated.sum())

    return on_step, counts


def cube_near_goal(env: Any, tolerance_m: float) -> torch.Tensor:
    from simlab.tasks.manager_based.manipulation.lift import mdp

    return mdp.object_reached_goal(env, "object_pose", threshold=tolerance_m)


def drawer_open(env: Any, min_opening_m: float) -> torch.Tensor:
    cabinet = env.scene["cabinet"]
    return cabinet.data.joint_pos[:, cabinet.joint_names.index("drawer_top_joint")] >= min_opening_m


def direct_cabinet_tracker(min_opening_m: float) -> tuple[Callable[[Any, Any, Any], None], dict[str, int]]:
    """An ``on_step`` hook for the direct cabinet: each finished episode's drawer opening, read from its
    final observation (an episode that pulls the drawer past 39 cm ends there, open)."""
    counts = {"success": 0, "episodes": 0}

    def on_step(env, obs, actions) -> None:
        from simlab.tasks.direct.franka_cabinet.franka_cabinet_env import DRAWER_OPENING_OBS

        finished = env.reset_buf  # the envs whose episode ended in this step (already reset)
        if not bool(finished.any()):
            return
        opening = env.extras["final_obs"]["policy"][:, DRAWER_OPENING_OBS]
        counts["success"] += int((finished & (opening >= min_opening_m)).sum())
        counts["episodes"] += int(finished.sum())

    return on_step, counts


def episodes_succeed(
    what: str, make_hook: Callable[[], tuple[Callable, dict[str, int]]], episode_s: float, rate: float = 0.8
) -> Criterion:
    def judge(result: dict[str, float], counts: dict[str, int]) -> tuple[float, bool]:
        if not counts["episodes"]:
            return 0.0, False
        share = counts["success"] / counts["episodes"]
        return share, share >= rate

    return Criterion(f">= {rate:.0%} of the episodes end with {what}", make_hook, judge, min_seconds=episode_s + 0.5)


class GaitRecorder:
    """An ``on_step`` hook: the played AMP humanoid against its clip (``scripts/benchmarks/amp_learn.py``).

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


def criterion_for(task: str, reward_threshold: float | None = None) -> Criterion:
    """The criterion of ``task`` (a Gymnasium id); ``reward_threshold`` replaces the stated one."""
    if reward_threshold is not None:
        return mean_reward_at_least(reward_threshold)
    if "Cartpole" in task:
        return pole_upright()
    if "Velocity-" in task:
        return tracks_velocity()
    if "Quadcopter" in task:
        return reaches_goal()
    if "Cart-Double-Pendulum" in task:
        return both_poles_upright()
    if "Reach-Franka" in task:
        return reaches_pose()
    if "Lift-Cube-Franka" in task:
        hook = partial(episode_end_tracker, partial(cube_near_goal, tolerance_m=0.05))
        return episodes_succeed("the cube within 0.05 m of its goal", hook, episode_s=5.0)
    if "Open-Drawer-Franka" in task:
        hook = partial(episode_end_tracker, partial(drawer_open, min_opening_m=0.2))
        return episodes_succeed("the top drawer open >= 0.2 m", hook, episode_s=8.0)
    if "Franka-Cabinet-Direct" in task:
        return episodes_succeed(
            "the top drawer open >= 0.2 m", partial(direct_cabinet_tracker, 0.2), episode_s=500 / 60
        )
    if "-AMP-" in task:  # its env reward is a constant; the motion itself is judged
        return imitates_clip()
    for robot, min_speed in FORWARD_SPEED_THRESHOLDS.items():
        if robot in task:
            return runs_forward(min_speed)
    raise ValueError(
        f"No solve criterion for {task}: the cartpole, cart double pendulum, velocity, quadcopter, Franka reach,"
        f" lift and cabinet, AMP and {list(FORWARD_SPEED_THRESHOLDS)} tasks have one; "
        "give --reward_threshold R to judge by the mean reward per env-step."
    )
