"""``simlab play``: load a checkpoint, export the policy, run it (record videos, report returns)."""

from __future__ import annotations

import argparse
import os
import time
from collections.abc import Callable
from typing import Any

import torch

from simlab.cli.checkpoints import (
    check_checkpoint_sizes,
    check_checkpoint_source,
    checkpoint_load_errors,
    env_sizes,
    find_last_checkpoint,
    note_missing_env_overrides,
    override_key,
    resolve_checkpoint,
)
from simlab.cli.libraries import get_library
from simlab.cli.runs import run_dir_of_checkpoint
from simlab.cli.session import ONE_VIDEO_INTERVAL, check_flags, load_configs, make_env
from simlab.cli.train import uses_multi_agent_learner
from simlab.rl.deploy_metadata import deploy_metadata
from simlab.utils.errors import ConfigError

__all__ = ["RealTimePacer", "choose_library", "locate_checkpoint", "rollout", "run_play"]


DEFAULT_LIBRARY = "rsl_rl"


def choose_library(args: argparse.Namespace) -> str:
    """``--library`` as given; without it, for ``--use_pretrained_checkpoint`` the library of the task's
    shipped policy where only one ships (said in a line), else rsl_rl. Isaac Lab's play scripts are one
    per library and name theirs (simlab.cli.isaaclab_scripts passes it), so this never overrules them."""
    if getattr(args, "library", None) is not None:
        return args.library
    if getattr(args, "use_pretrained_checkpoint", False):
        from simlab.pretrained import pretrained_libraries

        shipped = pretrained_libraries(args.task)
        if len(shipped) == 1:
            print(f"[simlab] Playing the {shipped[0]} policy shipped for {args.task} (--library {shipped[0]}).")
            return shipped[0]
    return DEFAULT_LIBRARY


def locate_checkpoint(args: argparse.Namespace, experiment: str) -> str:
    trust = getattr(args, "trust_checkpoint", False)
    if args.checkpoint:
        return resolve_checkpoint(args.checkpoint, args.library, trust)
    if args.use_last_checkpoint:
        return find_last_checkpoint(args.log_root, args.library, experiment, trust, task=args.task)
    if getattr(args, "use_pretrained_checkpoint", False):
        from simlab.pretrained import unpack_pretrained_checkpoint

        # the file written from the package's policy.pt: a newer one planted beside it is never picked
        return resolve_checkpoint(unpack_pretrained_checkpoint(args.task, args.library, args.log_root), args.library)
    raise ConfigError("play needs --checkpoint PATH, --use_last_checkpoint or --use_pretrained_checkpoint.")


CPU_PLAY_ENVS_NOTED = 1024  # more envs than this played on the CPU without --num_envs get a line


def _play_variant_envs_on_cpu(args: argparse.Namespace, env_cfg: Any, overrides: list[str]) -> None:
    """On the CPU, play a training task with its ``-Play`` variant's env count unless one is given: the
    training count (4096 G1s) took over 5 minutes for a 200-step video, the Play variant's 50 seconds."""
    import re

    import gymnasium as gym

    from simlab.tasks.utils import load_cfg_from_registry

    given = args.num_envs is not None or any(override_key(o) == "env.scene.num_envs" for o in overrides)
    if given or env_cfg.sim.device != "cpu":
        return
    variant = re.sub(r"(-v\d+)$", r"-Play\1", args.task)
    if variant == args.task or variant not in gym.registry:
        if env_cfg.scene.num_envs > CPU_PLAY_ENVS_NOTED:  # 8192 hands: about a second a step; say so
            print(
                f"[simlab] Playing the task's {env_cfg.scene.num_envs} envs on the CPU, which takes a while;"
                " --num_envs 16 plays a few."
            )
        return
    play_envs = load_cfg_from_registry(variant, "env_cfg_entry_point").scene.num_envs
    if play_envs < env_cfg.scene.num_envs:
        print(
            f"[simlab] Playing {play_envs} envs on the CPU, as {variant} does (the task trains"
            f" {env_cfg.scene.num_envs}); --num_envs N sets another count."
        )
        env_cfg.scene.num_envs = play_envs


def _total(x: Any) -> torch.Tensor:
    return sum(x.values()) if isinstance(x, dict) else x


def _any(x: Any) -> torch.Tensor:
    if isinstance(x, dict):
        out = torch.zeros_like(next(iter(x.values())), dtype=torch.bool)
        for v in x.values():
            out |= v.bool()
        return out
    return x.bool()


def rollout(
    env: Any,
    policy: Callable,
    steps: int | None,
    on_step: Callable[[Any, Any, Any], None] | None = None,
    stop_on_interrupt: bool = True,
    seed: int | None = None,
) -> dict[str, float]:
    """Step ``env`` with ``policy`` for ``steps`` (None: until Ctrl+C); episode statistics of the run
    and the mean reward per env-step.

    ``seed`` seeds torch before the reset, so a rollout with the same seed starts from the same
    states and draws the same commands: play and the checkpoint judge of ``simlab bench solve`` /
    make_pretrained play the same episodes. Ctrl+C ends the rollout with the statistics so far; with
    ``stop_on_interrupt`` False it propagates instead (a checkpoint's evaluation cut short is no
    verdict: the caller stops).
    """
    if seed is not None:
        torch.manual_seed(seed)
    obs, _ = env.reset()
    base = env.unwrapped
    returns = torch.zeros(base.num_envs, device=base.device)
    lengths = torch.zeros(base.num_envs, device=base.device)
    reward_sum = torch.zeros((), device=base.device)  # over all env-steps, on the device until the end
    done_returns: list[float] = []
    done_lengths: list[float] = []
    step = 0
    try:
        while steps is None or step < steps:
            actions = policy(obs)
            obs, rew, terminated, truncated, _ = env.step(actions)
            if on_step is not None:
                on_step(base, obs, actions)
            reward = _total(rew).reshape(-1).to(returns.device)
            returns += reward
            reward_sum += reward.sum()
            lengths += 1
            done = (_any(terminated) | _any(truncated)).reshape(-1).to(returns.device)
            if done.any():
                done_returns += returns[done].tolist()
                done_lengths += lengths[done].tolist()
                returns[done] = 0
                lengths[done] = 0
            step += 1
    except KeyboardInterrupt:
        if not stop_on_interrupt:
            raise
        print("\n[simlab] Stopped.")
    n = len(done_returns)
    return {
        "steps": step,
        "episodes": n,
        "mean_return": sum(done_returns) / n if n else float(returns.mean()),
        "mean_length": sum(done_lengths) / n if n else float(lengths.mean()),
        "mean_reward": float(reward_sum) / (step * base.num_envs) if step else float("nan"),  # per env-step
    }


def run_play(
    args: argparse.Namespace, overrides: list[str], on_step: Callable[[Any, Any, Any], None] | None = None
) -> dict[str, Any]:
    """Play ``args.task`` with a trained policy; returns the episode statistics and exported files."""
    check_flags(args)
    pretrained = getattr(args, "use_pretrained_checkpoint", False)
    if pretrained:
        from simlab.tasks.utils.parse_cfg import task_spec

        task_spec(args.task)  # a misspelled id is named as such, not as a task without a shipped policy
    args.library = choose_library(args)
    lib = get_library(args.library)
    if pretrained:
        from simlab.pretrained import pretrained_agent, pretrained_env_overrides

        trained_with = pretrained_env_overrides(args.task, args.library)
        if trained_with:
            print(f"[simlab] The pretrained policy was trained with {' '.join(trained_with)}; play uses the same.")
        overrides = [*trained_with, *overrides]
        agent = pretrained_agent(args.task, args.library)
        if agent and not getattr(args, "agent", None):  # e.g. a distilled student: its own agent config
            print(f"[simlab] The pretrained policy was made with --agent {agent}; play uses the same.")
            args.agent = agent
    env_cfg, agent_cfg = load_configs(args, overrides)
    _play_variant_envs_on_cpu(args, env_cfg, overrides)
    lib.configure(agent_cfg, args, env_cfg)
    checkpoint = locate_checkpoint(args, lib.experiment_name(agent_cfg, args.task))
    force, trust = getattr(args, "force", False), getattr(args, "trust_checkpoint", False)
    check_checkpoint_source(checkpoint, args.library, args.task, force=force, trust=trust)
    note_missing_env_overrides(checkpoint, overrides)
    run_dir = run_dir_of_checkpoint(checkpoint, args.library)
    args.video_interval = ONE_VIDEO_INTERVAL
    env = make_env(
        args, env_cfg, os.path.join(run_dir, "videos", "play"), single_agent=not uses_multi_agent_learner(args)
    )
    try:
        check_checkpoint_sizes(checkpoint, env_sizes(env), force=force)
        print(f"[simlab] Playing {checkpoint} on {env_cfg.sim.device}")
        with checkpoint_load_errors(checkpoint, args.library, args.task):
            policy = lib.load_policy(env, agent_cfg, checkpoint, trust=trust)
        result: dict[str, Any] = {"checkpoint": checkpoint}
        if not args.no_export and policy.not_exportable:
            print(f"[simlab] Not exported: {policy.not_exportable}")
        elif not args.no_export:
            folder = os.path.join(os.path.dirname(checkpoint), "exported")
            metadata = None if policy.multi_agent else deploy_metadata(env, args.task, policy.obs_groups)
            result["exported"] = policy.export(folder, metadata)
            print(f"[simlab] Exported the policy to {folder}: {[os.path.basename(f) for f in result['exported']]}")
        steps = args.steps
        if getattr(args, "seconds", None) is not None:
            steps = max(1, round(args.seconds / env.unwrapped.step_dt))
        if steps is None and (args.eval or args.video):
            steps = args.video_length if args.video else int(env.unwrapped.max_episode_length)
        result.update(rollout(env, policy, steps, on_step, seed=env_cfg.seed))
    finally:
        env.close()
    if args.eval:
        print(
            f"[simlab] {result['steps']} steps, {result['episodes']} finished episodes: "
            f"mean return {result['mean_return']:.3f}, mean length {result['mean_length']:.1f} steps"
        )
    return result


class RealTimePacer:
    """An ``on_step`` hook that sleeps so that each env step takes at least the env's ``step_dt``."""

    def __init__(self) -> None:
        self._last: float | None = None

    def __call__(self, env: Any, obs: Any, actions: Any) -> None:
        now = time.perf_counter()
        if self._last is not None:
            wait = float(env.step_dt) - (now - self._last)
            if wait > 0:
                time.sleep(wait)
        self._last = time.perf_counter()
