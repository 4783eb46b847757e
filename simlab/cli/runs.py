"""Run folders: ``logs/<library>/<experiment>/<timestamp>[_<run_name>]/``, their params and checkpoints."""

from __future__ import annotations

import os
import shlex
import sys
from datetime import datetime
from typing import Any

from simlab.tasks.utils import get_checkpoint_path
from simlab.utils.io import dump_yaml

__all__ = ["CHECKPOINT_LAYOUT", "dump_params", "find_last_checkpoint", "make_run_dir"]

# library -> (sub-folder of the run holding checkpoints, regex of checkpoint file names)
CHECKPOINT_LAYOUT: dict[str, tuple[list[str], str]] = {
    "rsl_rl": ([], r"model_\d+\.pt$"),
    "skrl": (["checkpoints"], r"agent_\d+\.pt$"),
    "sb3": ([], r"model(_\d+_steps)?\.zip$"),
    "rl_games": (["nn"], r".*\.pth$"),
}


def make_run_dir(log_root: str, library: str, experiment: str, run_name: str = "") -> str:
    """Create and return ``<log_root>/<library>/<experiment>/<timestamp>[_<run_name>]`` (absolute)."""
    stamp = datetime.now().strftime("%Y-%m-%d_%H-%M-%S")
    name = f"{stamp}_{run_name}" if run_name else stamp
    path = os.path.abspath(os.path.join(log_root, library, experiment, name))
    os.makedirs(path, exist_ok=True)
    return path


def dump_params(run_dir: str, env_cfg: Any, agent_cfg: Any, argv: list[str] | None = None) -> None:
    """Write ``params/env.yaml``, ``params/agent.yaml`` and the command line ``params/command.txt``."""
    params = os.path.join(run_dir, "params")
    dump_yaml(os.path.join(params, "env.yaml"), env_cfg)
    dump_yaml(os.path.join(params, "agent.yaml"), agent_cfg)
    argv = sys.argv if argv is None else argv
    with open(os.path.join(params, "command.txt"), "w") as f:
        f.write(shlex.join(["simlab" if a.endswith(("simlab", "__main__.py")) else a for a in argv[:1]] + argv[1:]))
        f.write("\n")


def find_last_checkpoint(log_root: str, library: str, experiment: str) -> str:
    """The newest checkpoint of the newest run of ``experiment``; a clear error says where it looked."""
    sub, pattern = CHECKPOINT_LAYOUT[library]
    log_path = os.path.join(log_root, library, experiment)
    try:
        return os.path.abspath(get_checkpoint_path(log_path, ".*", pattern, other_dirs=sub))
    except FileNotFoundError as e:
        raise FileNotFoundError(
            f"No checkpoint of '{experiment}' trained with {library}: {e} "
            f"Train first (simlab train --task ... --library {library}) or pass --checkpoint PATH."
        ) from e


def resolve_checkpoint(path: str, library: str) -> str:
    """``path`` if it is a checkpoint file; for a run folder, its newest checkpoint."""
    if os.path.isfile(path):
        return os.path.abspath(path)
    if os.path.isdir(path):
        sub, pattern = CHECKPOINT_LAYOUT[library]
        parent, run = os.path.split(os.path.abspath(path.rstrip("/")))
        return get_checkpoint_path(parent, f"^{run}$", pattern, other_dirs=sub)
    raise FileNotFoundError(f"Checkpoint '{path}' does not exist (looked at '{os.path.abspath(path)}').")


def run_dir_of_checkpoint(checkpoint: str, library: str) -> str:
    """The run folder that holds ``checkpoint``."""
    folder = os.path.dirname(os.path.abspath(checkpoint))
    for _ in CHECKPOINT_LAYOUT[library][0]:
        folder = os.path.dirname(folder)
    return folder
