"""``simlab train``: build the configs and the env, train with the chosen library, keep the run folder."""

from __future__ import annotations

import argparse
import os
import time
from typing import Any

from simlab.cli import distributed
from simlab.cli.checkpoints import (
    check_checkpoint_sizes,
    check_checkpoint_source,
    checkpoint_load_errors,
    env_sizes,
    resolve_checkpoint,
)
from simlab.cli.libraries import get_library
from simlab.cli.runs import dump_params, make_run_dir, remove_if_empty_run, write_run_info
from simlab.cli.session import check_flags, load_configs, make_env, resolve_seed
from simlab.rl.utils import is_multi_agent
from simlab.tasks.utils.hydra import env_overrides_in
from simlab.utils.errors import CheckpointError, ConfigError, StorageError, is_storage_error
from simlab.utils.startup import (
    bytecode_hint,
    clear_milestones,
    format_milestones,
    mark,
    resume_collector_after_start_up,
    seconds_since_process_start,
)

__all__ = [
    "launch_distributed",
    "needs_launch",
    "run_train",
    "seconds_since_process_start",
    "uses_multi_agent_learner",
]


def uses_multi_agent_learner(args: argparse.Namespace) -> bool:
    """True for skrl's IPPO / MAPPO, which take the multi-agent env as it is."""
    return args.library == "skrl" and (args.algorithm or "PPO") in ("IPPO", "MAPPO")


def _check_distributed_library(args: argparse.Namespace, device: str) -> None:
    if args.library not in distributed.SUPPORTED_LIBRARIES:
        raise ValueError(
            f"--distributed is not available for {args.library} (Stable-Baselines3 trains in one process). "
            f"Distributed training supports {list(distributed.SUPPORTED_LIBRARIES)}."
        )
    if args.library == "rl_games" and not device.startswith("cuda"):
        raise ValueError(
            "rl_games' multi_gpu mode runs on CUDA GPUs only (it starts an NCCL group); "
            "train on the CPU with --library rsl_rl or skrl."
        )


def needs_launch(args: argparse.Namespace) -> bool:
    """True for ``simlab train --distributed`` started outside torchrun: simlab launches torchrun."""
    return bool(args.distributed) and distributed.torchrun_ranks() is None


def launch_distributed(args: argparse.Namespace, argv: list[str]) -> int:
    """Run this ``simlab train`` command under torchrun, one process per GPU (or ``--nproc_per_node``)."""
    from simlab.utils.device import resolve_device

    device = resolve_device(args.device)
    _check_distributed_library(args, device)
    return distributed.launch(args, argv, device)


def _setup_ranks(args: argparse.Namespace, env_cfg: Any) -> distributed.Ranks:
    """This process's ranks; for ``--distributed``, its device and (for rsl_rl and skrl) the process group."""
    if not args.distributed:
        return distributed.Ranks()
    _check_distributed_library(args, env_cfg.sim.device)
    ranks = distributed.torchrun_ranks()
    if ranks is None or ranks.world_size < 2:
        raise ValueError(
            "--distributed needs at least 2 processes (WORLD_SIZE >= 2 under torchrun); "
            "start `simlab train --distributed` without torchrun to launch one process per GPU."
        )
    # rl_games' multi_gpu mode starts its own (NCCL) group; rsl_rl and skrl join the one started here
    env_cfg.sim.device = distributed.setup_process(env_cfg.sim.device, ranks, start_group=args.library != "rl_games")
    return ranks


def _ask_for_io_descriptors(args: argparse.Namespace, env_cfg: Any) -> None:
    """``--export_io_descriptors``: manager-based envs write them into the run folder when built."""
    if not getattr(args, "export_io_descriptors", False):
        return
    if hasattr(env_cfg, "export_io_descriptors"):
        env_cfg.export_io_descriptors = True
    else:
        print(
            f"[simlab] --export_io_descriptors: {args.task} is a direct task, which has no observation or action "
            "terms to describe; IO descriptors exist for manager-based tasks only. Training goes on without them."
        )


def _settings_all_ranks_share(args: argparse.Namespace, overrides: list[str], env: Any) -> dict[str, Any]:
    """What must be equal on every rank for the library's collectives to line up."""
    unwrapped = env.unwrapped
    return {
        "task": args.task,
        "library": args.library,
        "algorithm": args.algorithm,
        "num_envs": unwrapped.num_envs,
        "max_iterations": args.max_iterations,
        "checkpoint": args.checkpoint,
        "overrides": sorted(overrides),
        "observation_space": str(getattr(unwrapped, "single_observation_space", None)),
        "action_space": str(getattr(unwrapped, "single_action_space", None)),
    }


def run_train(args: argparse.Namespace, overrides: list[str], argv: list[str] | None = None) -> str | None:
    """Train ``args.task`` with ``args.library``; returns the run folder (None on ranks other than 0)."""
    clear_milestones()
    mark("command")
    check_flags(args)
    if getattr(args, "ml_framework", "torch") != "torch" and args.library != "skrl":
        raise ConfigError(f"--ml_framework {args.ml_framework} is skrl's; {args.library} trains on torch.")
    args.seed = resolve_seed(args.seed)
    env_cfg, agent_cfg = load_configs(args, overrides)
    mark("configs")
    _ask_for_io_descriptors(args, env_cfg)
    ranks = _setup_ranks(args, env_cfg)
    lib = get_library(args.library)
    mark("library")
    lib.configure(agent_cfg, args, env_cfg)
    if not getattr(lib, "READS_FINAL_OBS", True) and hasattr(env_cfg, "final_observations"):
        env_cfg.final_observations = False  # training only: play's success criteria read them
    # seed + rank: each rank simulates other episodes (the env seeds torch with it; skrl and rl_games
    # add the rank to their own seeds themselves)
    env_cfg.seed = None if env_cfg.seed is None else env_cfg.seed + ranks.rank
    trust = getattr(args, "trust_checkpoint", False)
    distilling = getattr(lib, "needs_teacher", lambda cfg: False)(agent_cfg)
    if distilling and not args.checkpoint:
        raise ConfigError(
            f"Distillation ({args.agent or 'this agent'}) needs the teacher's checkpoint: pass --checkpoint <the"
            f" teacher's run folder or model_<N>.pt> (Isaac Lab's train.py: --load_run <run>). Train the teacher"
            f" first, e.g. simlab train --task {args.task}."
        )
    resume = resolve_checkpoint(args.checkpoint, args.library, trust) if args.checkpoint else None
    # a teacher may come from another task (a state policy teaches a camera one): its fit is its layer sizes
    of_this_task = resume is not None and not (distilling and lib.is_teacher_checkpoint(resume, trust))
    if of_this_task:
        check_checkpoint_source(resume, args.library, args.task, force=getattr(args, "force", False), trust=trust)
    _resolve_init_weights(args, lib, trust)
    run_dir = None
    if ranks.is_main:  # only rank 0 writes the run folder
        run_dir = make_run_dir(args.log_root, args.library, lib.experiment_name(agent_cfg, args.task), args.run_name)
    try:
        startup, start = _train_in(
            run_dir, ranks, lib, args, overrides, env_cfg, agent_cfg, resume, argv, of_this_task, distilling
        )
    except BaseException as error:
        removed = run_dir is not None and remove_if_empty_run(run_dir, args.library)
        if removed:
            print(f"[simlab] Removed the run folder {run_dir}: the run stopped before its first checkpoint.")
        if run_dir is not None and is_storage_error(error):
            raise StorageError(_stopped_writing(run_dir, args.library, error, removed)) from error
        raise
    finally:
        distributed.shutdown()
    took = time.perf_counter() - start
    if ranks.is_main:
        if getattr(args, "verbose", False):
            print(format_milestones())
        print(
            f"[simlab] Training took {took:.1f} s after {startup:.1f} s of start-up "
            f"({startup + took:.1f} s in all). Run folder: {run_dir}"
        )
    return run_dir


def _resolve_init_weights(args: argparse.Namespace, lib: Any, trust: bool) -> None:
    """``--init_weights`` (and ``--warmup_critic``): refuse it with ``--checkpoint`` or a library that cannot
    take it, or a checkpoint of another library; else make ``args.init_weights`` its absolute path (its
    task may differ)."""
    warmup = getattr(args, "warmup_critic", 0)
    if warmup < 0:
        raise ConfigError(f"--warmup_critic must be >= 0 (iterations that train the critic only), got {warmup}.")
    if not getattr(args, "init_weights", None):
        if warmup:
            raise ConfigError("--warmup_critic warms up a critic for weights given by --init_weights: give that too.")
        return
    if args.checkpoint:
        raise ConfigError(
            "--init_weights starts a new run from a checkpoint's weights and --checkpoint resumes a run: give one."
        )
    if not hasattr(lib, "init_weights"):
        raise ConfigError(
            f"--init_weights is supported with --library rsl_rl, not {args.library}; --checkpoint resumes a"
            f" {args.library} run of this task."
        )
    args.init_weights = resolve_checkpoint(args.init_weights, args.library, trust)
    check_checkpoint_source(args.init_weights, args.library, None, force=getattr(args, "force", False), trust=trust)


def _stopped_writing(run_dir: str, library: str, error: BaseException, removed: bool) -> str:
    """One line for a training whose run folder could not be written: where, why, and what is kept."""
    what = str(error) if isinstance(error, StorageError) else f"Cannot write into '{run_dir}': {error.strerror}."
    if removed:
        return f"{what} Training stopped before its first checkpoint."
    try:
        last = resolve_checkpoint(run_dir, library)
    except CheckpointError:
        return f"{what} Training stopped; no complete checkpoint is left in '{run_dir}'."
    return f"{what} Training stopped; its last complete checkpoint is '{last}'."


def _train_in(
    run_dir: str | None,
    ranks: distributed.Ranks,
    lib: Any,
    args: argparse.Namespace,
    overrides: list[str],
    env_cfg: Any,
    agent_cfg: Any,
    resume: str | None,
    argv: Any,
    of_this_task: bool = True,
    distilling: bool = False,
) -> tuple[float, float]:
    """Write the run's params (rank 0), build the env and train; returns the start-up time and when
    training began."""
    if run_dir is not None:
        if hasattr(env_cfg, "log_dir"):
            env_cfg.log_dir = run_dir
        dump_params(run_dir, env_cfg, agent_cfg, argv)
    elif getattr(env_cfg, "export_io_descriptors", False):
        env_cfg.export_io_descriptors = False  # rank 0 writes them, into its run folder
    multi = uses_multi_agent_learner(args)
    video_dir = os.path.join(run_dir, "videos", "train") if run_dir else None
    env = make_env(args, env_cfg, video_dir, single_agent=not multi)
    mark("env")
    try:
        if multi and not is_multi_agent(env):
            raise ConfigError(f"--algorithm {args.algorithm} needs a multi-agent task; {args.task} has one agent.")
        sizes = env_sizes(env)
        if resume and of_this_task:
            check_checkpoint_sizes(resume, sizes, force=getattr(args, "force", False))
        init = getattr(args, "init_weights", None)
        if init:  # another task's weights fit when its sizes are this env's
            check_checkpoint_sizes(init, sizes, force=getattr(args, "force", False))
        args.shared_settings = _settings_all_ranks_share(args, overrides, env)
        if ranks.world_size > 1 and args.library != "rl_games":  # rl_games checks once its agent started the group
            distributed.check_same_settings(args.shared_settings)
        if run_dir is not None:
            algorithm = "Distillation" if distilling else args.algorithm or "PPO"
            info = {"task": args.task, "library": args.library, "algorithm": algorithm, **sizes}
            if resume and not of_this_task:  # the teacher's checkpoint, which the student learned from
                info["teacher"] = resume
            env_overrides = env_overrides_in(overrides)
            if env_overrides:  # named when a play without them does not fit the checkpoint
                info["env_overrides"] = env_overrides
            if init:  # where its weights started (fine-tuned from another task's policy, say)
                info["init_weights"] = init
            write_run_info(run_dir, info)
            spread = f" on each of {ranks.world_size} processes" if ranks.world_size > 1 else ""
            print(
                f"[simlab] Training {args.task} with {args.library} on {env_cfg.sim.device}, "
                f"{env.unwrapped.num_envs} envs{spread}. Run folder: {run_dir}"
            )
            hint = bytecode_hint()
            if hint:
                print(hint)
        resume_collector_after_start_up()  # paused by the `simlab` command for its imports and env build
        startup = seconds_since_process_start()
        start = time.perf_counter()
        with checkpoint_load_errors(resume or init, args.library, args.task, only_state_dicts=True):
            lib.train(env, agent_cfg, run_dir, args, resume)
    finally:
        env.close()
    return startup, start
