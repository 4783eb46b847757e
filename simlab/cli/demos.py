"""``simlab record`` / ``simlab replay``: demonstrations in an HDF5 dataset (Isaac Lab's
``record_demos.py`` / ``replay_demos.py`` for a manager-based task).

``record`` steps the task with scripted (seeded random, or zero) actions and records each finished
episode with ``ActionStateRecorderManagerCfg``: its initial state, actions, policy observations and
the state after every step. ``replay`` puts an env in each episode's initial state
(``env.reset_to``), steps the recorded actions with the task's terminations off (as Isaac Lab's
replay does) and, with ``--validate_states``, compares every state with the recorded one.
On the CPU a replay is bit-identical.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Callable
from typing import Any

import gymnasium as gym
import torch

from simlab.cli.session import load_configs
from simlab.utils.datasets import EpisodeData
from simlab.utils.errors import ConfigError

__all__ = ["add_demo_recorders", "run_record", "run_replay"]


def _manager_based(env: gym.Env, command: str) -> None:
    if not hasattr(env.unwrapped, "recorder_manager"):
        raise ConfigError(f"simlab {command} needs a manager-based task (one with a recorder manager).")


def add_demo_recorders(env_cfg: Any, path: str, task: str, succeeded_only: bool = False) -> None:
    """Give ``env_cfg`` the recorders of a demonstration (``ActionStateRecorderManagerCfg``, and the
    subtask signals where the task has a ``subtask_terms`` group), writing to ``path`` (``.hdf5``): every
    finished episode, or with ``succeeded_only`` those its ``success`` termination ended."""
    from simlab.envs.mdp.recorders import ActionStateRecorderManagerCfg, PreStepSubtaskTermsObservationsRecorderCfg
    from simlab.managers import DatasetExportMode

    stem, extension = os.path.splitext(os.path.abspath(path))
    if extension != ".hdf5":  # the recorder names its file <stem>.hdf5
        raise ConfigError(f"--dataset_file must end with .hdf5 (the recorder writes HDF5), got '{path}'.")
    env_cfg.recorders = ActionStateRecorderManagerCfg(
        dataset_export_dir_path=os.path.dirname(stem), dataset_filename=os.path.basename(stem)
    )
    if succeeded_only:
        env_cfg.recorders.dataset_export_mode = DatasetExportMode.EXPORT_SUCCEEDED_ONLY
    if getattr(env_cfg.observations, "subtask_terms", None) is not None:  # what demonstration tools split by
        env_cfg.recorders.record_pre_step_subtask_term_signals = PreStepSubtaskTermsObservationsRecorderCfg()
    env_cfg.env_name = task  # the recorder stores it: replay refuses another task's episodes


def run_record(args: argparse.Namespace, overrides: list[str]) -> int:
    """Record ``args.num_demos`` finished episodes of ``args.task`` into ``args.dataset_file``."""
    from simlab.utils.datasets import HDF5DatasetFileHandler  # noqa: F401 - without h5py: say so before recording

    if args.num_demos < 1:
        raise ConfigError(f"--num_demos must be at least 1, got {args.num_demos}.")
    path = os.path.abspath(args.dataset_file)
    if os.path.exists(path) and not args.overwrite:
        raise ConfigError(f"{path} exists: give another --dataset_file, or --overwrite to replace its episodes.")
    env_cfg, _ = load_configs(args, overrides, with_agent=False)
    add_demo_recorders(env_cfg, path, args.task)
    env_cfg.seed = args.seed if args.seed is not None else 0
    env = gym.make(args.task, cfg=env_cfg).unwrapped
    _manager_based(env, "record")
    generator = torch.Generator(device=env.device).manual_seed(env_cfg.seed)
    width = env.action_manager.total_action_dim
    env.reset()
    recorded = 0
    try:
        while recorded < args.num_demos:
            if args.actions == "zero":
                action = torch.zeros(env.num_envs, width, device=env.device)
            else:
                action = torch.rand(env.num_envs, width, device=env.device, generator=generator) * 2 - 1
            env.step(action)
            manager = env.recorder_manager
            recorded = manager.exported_successful_episode_count + manager.exported_failed_episode_count
    finally:
        env.close()
    print(f"[simlab] recorded {recorded} episodes of {args.task} into {path}")
    return 0


def run_replay(args: argparse.Namespace, overrides: list[str], on_episode: Callable | None = None) -> int:
    """Replay the episodes of ``args.dataset_file`` one by one in a single env; returns 0, or 1 when
    ``--validate_states`` found a state that differs from the recorded one."""
    from simlab.utils.datasets import HDF5DatasetFileHandler

    handler = HDF5DatasetFileHandler()
    handler.open(args.dataset_file)
    names = list(handler.get_episode_names())
    selected = names if not args.select_episodes else [f"demo_{i}" for i in args.select_episodes]
    missing = [n for n in selected if n not in names]
    if missing:
        raise ConfigError(f"{args.dataset_file} has no episode {missing}; it has {names}.")
    recorded_task = handler.get_env_name()
    if recorded_task and recorded_task != args.task:
        raise ConfigError(
            f"{args.dataset_file} holds episodes of {recorded_task}, not {args.task}: "
            f"replay it with --task {recorded_task}."
        )
    args.num_envs = 1
    env_cfg, _ = load_configs(args, overrides, with_agent=False)
    env_cfg.recorders = None
    env_cfg.terminations = None  # the recorded episode decides when it ends
    env = gym.make(args.task, cfg=env_cfg).unwrapped
    _manager_based(env, "replay")
    env.reset()
    all_identical = True
    try:
        for name in selected:
            episode = handler.load_episode(name, env.device)
            _check_episode(episode, name, args.dataset_file, env.action_manager.total_action_dim)
            env.reset_to(episode.get_initial_state(), torch.tensor([0], device=env.device), is_relative=True)
            steps, deviation = 0, 0.0
            while (action := episode.get_next_action()) is not None:
                env.step(action.unsqueeze(0))
                steps += 1
                if args.validate_states:
                    deviation = max(
                        deviation, _deviation(env.scene.get_state(is_relative=True), episode.get_next_state())
                    )
            report = f"[simlab] {name}: {steps} steps replayed"
            if args.validate_states:
                all_identical &= deviation == 0.0
                report += ", states bit-identical" if deviation == 0.0 else f", largest state deviation {deviation:.3g}"
            print(report)
            if on_episode is not None:
                on_episode(name, steps, deviation)
    finally:
        env.close()
        handler.close()
    return 0 if all_identical else 1


def _check_episode(episode: EpisodeData, name: str, path: str, action_dim: int) -> None:
    """Refuse an episode this env cannot replay: no initial state, or actions of another width (a file
    recorded on another task before simlab stored the task's name)."""
    actions = episode.data.get("actions")
    if not isinstance(actions, torch.Tensor) or actions.ndim != 2 or episode.get_initial_state() is None:
        raise ConfigError(
            f"{path} {name} is not a recorded episode: it needs 'actions' (steps x width) and 'initial_state'."
        )
    if actions.shape[1] != action_dim:
        raise ConfigError(
            f"{path} {name} has actions of width {actions.shape[1]}; this task's are {action_dim} wide: "
            "it was recorded on another task."
        )


def _deviation(state: dict | torch.Tensor, recorded: dict | torch.Tensor | None) -> float:
    """Largest absolute difference between a live state (one env) and a recorded step's state."""
    if recorded is None:
        raise ConfigError("The dataset has fewer recorded states than actions; it cannot be validated.")
    if isinstance(state, dict):
        return max((_deviation(state[k], recorded[k]) for k in recorded), default=0.0)
    return (state[0] - recorded.to(state.device)).abs().max().item()
