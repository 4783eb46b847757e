"""``simlab train``: build the configs and the env, train with the chosen library, keep the run folder."""

from __future__ import annotations

import argparse
import os
import time

from simlab.cli.libraries import get_library
from simlab.cli.runs import dump_params, make_run_dir, resolve_checkpoint
from simlab.cli.session import load_configs, make_env, resolve_seed
from simlab.rl.utils import is_multi_agent

__all__ = ["run_train", "uses_multi_agent_learner"]


def uses_multi_agent_learner(args: argparse.Namespace) -> bool:
    """True for skrl's IPPO / MAPPO, which take the multi-agent env as it is."""
    return args.library == "skrl" and (args.algorithm or "PPO") in ("IPPO", "MAPPO")


def run_train(args: argparse.Namespace, overrides: list[str], argv: list[str] | None = None) -> str:
    """Train ``args.task`` with ``args.library``; returns the run folder."""
    if args.distributed:
        raise NotImplementedError("--distributed (multi-GPU) training is not yet supported by simlab.")
    lib = get_library(args.library)
    args.seed = resolve_seed(args.seed)
    env_cfg, agent_cfg = load_configs(args, overrides)
    lib.configure(agent_cfg, args, env_cfg)
    resume = resolve_checkpoint(args.checkpoint, args.library) if args.checkpoint else None
    run_dir = make_run_dir(args.log_root, args.library, lib.experiment_name(agent_cfg, args.task), args.run_name)
    if hasattr(env_cfg, "log_dir"):
        env_cfg.log_dir = run_dir
    dump_params(run_dir, env_cfg, agent_cfg, argv)

    multi = uses_multi_agent_learner(args)
    env = make_env(args, env_cfg, os.path.join(run_dir, "videos", "train"), single_agent=not multi)
    if multi and not is_multi_agent(env):
        env.close()
        raise ValueError(f"--algorithm {args.algorithm} needs a multi-agent task; {args.task} has one agent.")
    print(
        f"[simlab] Training {args.task} with {args.library} on {env_cfg.sim.device}, "
        f"{env.unwrapped.num_envs} envs. Run folder: {run_dir}"
    )
    start = time.time()
    try:
        lib.train(env, agent_cfg, run_dir, args, resume)
    finally:
        env.close()
    print(f"[simlab] Training took {time.time() - start:.1f} s. Run folder: {run_dir}")
    return run_dir
