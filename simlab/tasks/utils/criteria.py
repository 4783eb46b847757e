"""Success criteria: when is a task solved? A task registers its criterion with Gymnasium, beside its
agent configs (``success_criterion_entry_point``: ``"module:factory"``, a function of no arguments
returning a :class:`Criterion`); ``simlab bench solve``, ``scripts/make_pretrained.py`` and the
pretrained-policy test read it with :func:`criterion_for`. The criteria several tasks share live
here; one task's own lives in its folder (``criterion.py``).

Here: the cartpoles (|pole angle| < 0.2 rad in >= 95 % of the env-steps), the ant and humanoid
(mean torso speed towards the target, +x where the tasks' target lies 1 km away, falls and resets
included: a speed, not a reward, as the manager-based tasks' rewards are scaled by the step time and
the direct ones' are not), episodes judged at their end (the manipulation tasks), and a mean reward
per env-step (any task, when a threshold is given).

Criteria that judge whole episodes or command windows state how long a play must at least last
(``Criterion.min_seconds``); :meth:`Criterion.play_seconds` lengthens a shorter request to it.
A criterion that judges a play unlike training's names its env overrides (``Criterion.play_overrides``).
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import gymnasium as gym
import torch

__all__ = [
    "Criterion",
    "criterion_for",
    "episode_end_tracker",
    "episodes_succeed",
    "mean_reward_at_least",
    "pole_angle_tracker",
    "pole_upright",
    "runs_forward",
    "wrapped_angle",
]

ENTRY_POINT = "success_criterion_entry_point"

# Mean torso speed towards the target [m/s] a played policy must keep. Measured on the CPU (64 envs,
# 5 s): untrained policies of Ant-v0 and Humanoid-v0 -0.03 and 0.03 m/s; the shipped Ant-Direct-v0
# and Humanoid-Direct-v0 policies 7.4 and 3.0 m/s.
MIN_FORWARD_SPEED = 1.0


@dataclass
class Criterion:
    """What a played policy must show; ``judge`` turns a rollout into (score, passed)."""

    description: str
    make_hook: Callable[[], tuple[Callable | None, Any]]
    judge: Callable[[dict[str, float], Any], tuple[float, bool]]
    min_seconds: float = 0.0  # a shorter play sees no finished episode or command window
    play_overrides: tuple[str, ...] = ()
    """``env.*`` overrides of the play it judges, where that differs from training's env (a clip played
    through from its start, without pushes); the evaluation applies them after the run's own."""

    def play_seconds(self, requested: float) -> float:
        """How long to play for a verdict: ``requested``, or ``min_seconds`` where that is longer."""
        return max(requested, self.min_seconds)


def criterion_for(task: str, reward_threshold: float | None = None) -> Criterion:
    """The criterion ``task`` (a Gymnasium id) registered; ``reward_threshold`` replaces it with a mean
    reward per env-step."""
    if reward_threshold is not None:
        return mean_reward_at_least(reward_threshold)
    if task not in gym.registry:
        raise ValueError(f"Unknown task {task}; `simlab list` prints the registered ones.")
    entry_point = gym.spec(task).kwargs.get(ENTRY_POINT)
    if entry_point is None:
        raise ValueError(
            f"No solve criterion for {task}: it registers no {ENTRY_POINT} (a 'module:factory' beside its agent"
            " configs); give --reward_threshold R to judge by the mean reward per env-step."
        )
    module, _, name = entry_point.partition(":")
    return getattr(importlib.import_module(module), name)()


def mean_reward_at_least(threshold: float) -> Criterion:
    def judge(result: dict[str, float], _: Any) -> tuple[float, bool]:
        return result["mean_reward"], result["mean_reward"] >= threshold

    return Criterion(f"mean reward per env-step >= {threshold:g}", lambda: (None, None), judge)


def wrapped_angle(angle: torch.Tensor) -> torch.Tensor:
    """``angle`` wrapped into [-pi, pi)."""
    return torch.remainder(angle + math.pi, 2 * math.pi) - math.pi


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
        angle = wrapped_angle(angle)
        counts["inside"] += int((angle.abs() < threshold).sum())
        counts["total"] += angle.numel()

    return on_step, counts


def pole_upright(threshold: float = 0.2, fraction: float = 0.95) -> Criterion:
    def judge(result: dict[str, float], counts: dict[str, int]) -> tuple[float, bool]:
        inside = counts["inside"] / max(1, counts["total"])
        return inside, inside >= fraction

    return Criterion(
        f"|pole angle| < {threshold} rad in >= {fraction:.0%} of steps",
        lambda: pole_angle_tracker(threshold),
        judge,
    )


def forward_speed_tracker() -> tuple[Callable[[Any, Any, Any], None], dict[str, float]]:
    """An ``on_step`` hook summing the root's world-frame x velocity (towards the target) over env-steps."""
    sums = {"speed": 0.0, "total": 0}

    def on_step(env, obs, actions) -> None:
        velocity = env.unwrapped.scene["robot"].data.root_lin_vel_w
        sums["speed"] += float(velocity[:, 0].sum())
        sums["total"] += velocity.shape[0]

    return on_step, sums


def runs_forward(min_speed: float = MIN_FORWARD_SPEED) -> Criterion:
    def judge(result: dict[str, float], sums: dict[str, float]) -> tuple[float, bool]:
        speed = sums["speed"] / max(1, sums["total"])
        return speed, sums["total"] > 0 and speed >= min_speed

    return Criterion(f"mean torso speed towards the target >= {min_speed:g} m/s", forward_speed_tracker, judge)


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


def episodes_succeed(
    what: str, make_hook: Callable[[], tuple[Callable, dict[str, int]]], episode_s: float, rate: float = 0.8
) -> Criterion:
    def judge(result: dict[str, float], counts: dict[str, int]) -> tuple[float, bool]:
        if not counts["episodes"]:
            return 0.0, False
        share = counts["success"] / counts["episodes"]
        return share, share >= rate

    return Criterion(f">= {rate:.0%} of the episodes end with {what}", make_hook, judge, min_seconds=episode_s + 0.5)
