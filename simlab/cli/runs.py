"""Run folders: ``logs/<library>/<experiment>/<timestamp>[_<run_name>]/``, their params and their clean-up."""

from __future__ import annotations

import os
import re
import shlex
import shutil
import sys
from datetime import datetime
from typing import Any

from simlab.envs.utils.spaces import replace_env_cfg_spaces_with_strings, replace_strings_with_env_cfg_spaces
from simlab.utils.errors import StorageError
from simlab.utils.io import dump_yaml, load_yaml, write_text

__all__ = [
    "CHECKPOINT_LAYOUT",
    "RUN_INFO",
    "dump_params",
    "find_run_info",
    "holds_checkpoint",
    "is_checkpoint_name",
    "make_run_dir",
    "remove_if_empty_run",
    "run_dir_of_checkpoint",
    "write_run_info",
]

# library -> (sub-folder of the run holding checkpoints, regex of checkpoint file names)
CHECKPOINT_LAYOUT: dict[str, tuple[list[str], str]] = {
    "rsl_rl": ([], r"model_\d+\.pt$"),
    "skrl": (["checkpoints"], r"agent_\d+\.pt$"),
    "sb3": ([], r"model(_\d+_steps)?\.zip$"),
    "rl_games": (["nn"], r".*\.pth$"),
    "bc": ([], r".*\.pt$"),  # scripts/imitation_learning/bc.py train --out <name>.pt
}
# what a run was trained on: task, library, observation and action sizes (checked by play and resume)
RUN_INFO = os.path.join("params", "run.yaml")


def make_run_dir(log_root: str, library: str, experiment: str, run_name: str = "") -> str:
    """Create and return a new ``<log_root>/<library>/<experiment>/<timestamp>[_<run_name>]`` (absolute).

    The folder is created with one ``mkdir``, which fails if it exists: two runs started in the
    same second get ``<name>``, ``<name>_1``, ... and never share a folder.
    """
    stamp = datetime.now().strftime("%Y-%m-%d_%H-%M-%S")
    name = f"{stamp}_{run_name}" if run_name else stamp
    parent = os.path.abspath(os.path.join(log_root, library, experiment))
    try:
        os.makedirs(parent, exist_ok=True)
        for attempt in range(1000):
            path = os.path.join(parent, name if attempt == 0 else f"{name}_{attempt}")
            try:
                os.mkdir(path)
                return path
            except FileExistsError:
                continue
    except OSError as error:  # read-only, no permission, a file where a folder should be, a full disk
        raise StorageError(
            f"Cannot create a run folder in '{parent}': {error.strerror or error}. Give a --log_root you can write."
        ) from error
    raise FileExistsError(f"Could not create a new run folder for '{name}' in '{parent}' (1000 taken).")


def dump_params(run_dir: str, env_cfg: Any, agent_cfg: Any, argv: list[str] | None = None) -> None:
    """Write ``params/env.yaml``, ``params/agent.yaml`` and the command line ``params/command.txt``."""
    params = os.path.join(run_dir, "params")
    # Gymnasium spaces are written as Isaac Lab writes them (JSON strings), then put back
    replace_env_cfg_spaces_with_strings(env_cfg)
    try:
        dump_yaml(os.path.join(params, "env.yaml"), env_cfg)
    finally:
        replace_strings_with_env_cfg_spaces(env_cfg)
    dump_yaml(os.path.join(params, "agent.yaml"), agent_cfg)
    argv = sys.argv if argv is None else argv
    command = shlex.join(["simlab" if a.endswith(("simlab", "__main__.py")) else a for a in argv[:1]] + argv[1:])
    write_text(os.path.join(params, "command.txt"), command + "\n")


def write_run_info(run_dir: str, info: dict[str, Any]) -> None:
    """Write ``params/run.yaml``: the task, library and sizes the run's checkpoints belong to."""
    dump_yaml(os.path.join(run_dir, RUN_INFO), info)


def find_run_info(checkpoint: str) -> dict[str, Any] | None:
    """The ``params/run.yaml`` of the run holding ``checkpoint`` (its folder or up to two above), or None."""
    folder = os.path.dirname(os.path.abspath(checkpoint))
    for _ in range(3):
        path = os.path.join(folder, RUN_INFO)
        if os.path.isfile(path):
            return load_yaml(path)
        folder = os.path.dirname(folder)
    return None


def is_checkpoint_name(name: str, library: str) -> bool:
    """True if a file named ``name`` is one of ``library``'s checkpoints (the whole name must match)."""
    return re.match(CHECKPOINT_LAYOUT[library][1], name) is not None


def holds_checkpoint(run_dir: str, library: str) -> bool:
    """True if the run folder holds at least one checkpoint file of ``library``."""
    folder = os.path.join(run_dir, *CHECKPOINT_LAYOUT[library][0])
    return os.path.isdir(folder) and any(is_checkpoint_name(f, library) for f in os.listdir(folder))


def remove_if_empty_run(run_dir: str, library: str) -> bool:
    """Remove a run folder that holds no checkpoint and no video (a start that failed); True if removed."""
    if not os.path.isdir(run_dir) or holds_checkpoint(run_dir, library):
        return False
    for _, _, files in os.walk(os.path.join(run_dir, "videos")):
        if any(f.endswith(".mp4") for f in files):
            return False
    shutil.rmtree(run_dir, ignore_errors=True)
    return True


def run_dir_of_checkpoint(checkpoint: str, library: str) -> str:
    """The run folder that holds ``checkpoint`` (checkpoint files of some libraries are in a sub-folder)."""
    folder = os.path.dirname(os.path.abspath(checkpoint))
    for _ in CHECKPOINT_LAYOUT[library][0]:
        folder = os.path.dirname(folder)
    return folder
