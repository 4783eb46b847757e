"""``simlab train``: build the configs and the env, train with the chosen library, keep the run folder."""

from __future__ import annotations

import argparse
import os
import time
from typing import Any

from simlab.cli.checkpoints import check_checkpoint_sizes, check_checkpoint_source, env_sizes, resolve_checkpoint
from simlab.cli.libraries import get_library
from simlab.cli.runs import dump_params, make_run_dir, remove_if_empty_run, write_run_info
from simlab.cli.session import check_flags, load_configs, make_env, resolve_seed
from simlab.rl.utils import is_multi_agent
from simlab.utils.errors import ConfigError

__all__ = ["run_train", "uses_multi_agent_learner"]


def uses_multi_agent_learner(args: argparse.Namespace) -> bool:
    """True for skrl's IPPO / MAPPO, which take the multi-agent env as it is."""
    return args.library == "skrl" and (args.algorithm or "PPO") in ("IPPO", "MAPPO")


def run_train(args: argparse.Namespace, overrides: list[str], argv: list[str] | None = None) -> str:
    """Train ``args.task`` with ``args.library``; returns the run folder."""
    if args.distributed:
        raise NotImplementedError("--distributed (multi-GPU) training is not yet supported by simlab.")
    check_flags(args)
    lib = get_library(args.library)
    args.seed = resolve_seed(args.seed)
    env_cfg, agent_cfg = load_configs(args, overrides)
    lib.configure(agent_cfg, args, env_cfg)
    resume = resolve_checkpoint(args.checkpoint, args.library) if args.checkpoint else None
    if resume:
        check_checkpoint_source(resume, args.library, args.task, force=getattr(args, "force", False))
    run_dir = make_run_dir(args.log_root, args.library, lib.experiment_name(agent_cfg, args.task), args.run_name)
    try:
        startup, start = _train_in(run_dir, lib, args, env_cfg, agent_cfg, resume, argv)
    except BaseException:
        if remove_if_empty_run(run_dir, args.library):
            print(f"[simlab] Removed the run folder {run_dir}: the run stopped before its first checkpoint.")
        raise
    took = time.perf_counter() - start
    print(
        f"[simlab] Training took {took:.1f} s after {startup:.1f} s of start-up "
        f"({startup + took:.1f} s in all). Run folder: {run_dir}"
    )
    return run_dir


def _train_in(
    run_dir: str, lib: Any, args: argparse.Namespace, env_cfg: Any, agent_cfg: Any, resume: str | None, argv: Any
) -> tuple[float, float]:
    """Write the run's params, build the env and train; returns the start-up time and when training began."""
    if hasattr(env_cfg, "log_dir"):
        env_cfg.log_dir = run_dir
    dump_params(run_dir, env_cfg, agent_cfg, argv)
    multi = uses_multi_agent_learner(args)
    env = make_env(args, env_cfg, os.path.join(run_dir, "videos", "train"), single_agent=not multi)
    try:
        if multi and not is_multi_agent(env):
            raise ConfigError(f"--algorithm {args.algorithm} needs a multi-agent task; {args.task} has one agent.")
        sizes = env_sizes(env)
        if resume:
            check_checkpoint_sizes(resume, sizes, force=getattr(args, "force", False))
        info = {"task": args.task, "library": args.library, "algorithm": args.algorithm or "PPO", **sizes}
        write_run_info(run_dir, info)
        print(
            f"[simlab] Training {args.task} with {args.library} on {env_cfg.sim.device}, "
            f"{env.unwrapped.num_envs} envs. Run folder: {run_dir}"
        )
        startup = seconds_since_process_start()
        start = time.perf_counter()
        lib.train(env, agent_cfg, run_dir, args, resume)
    finally:
        env.close()
    return startup, start


def seconds_since_process_start() -> float:
    """Wall time since this process started (Linux's /proc; NaN elsewhere)."""
    try:
        with open("/proc/self/stat") as f:
            start_ticks = int(f.read().rsplit(")", 1)[1].split()[19])  # field 22: starttime
        with open("/proc/uptime") as f:
            uptime = float(f.read().split()[0])
        return uptime - start_ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        return float("nan")
