"""Checkpoints of runs: find the newest readable one, and check that it fits the task and library.

A checkpoint is *readable* when its library's loader can open it (``torch.load`` for ``.pt`` /
``.pth``, a complete zip archive for Stable-Baselines3). A torn or corrupt newest file is skipped
with a warning that names the file used instead. A checkpoint *fits* when it was written by the
same library for the same task with the same observation and action sizes (``params/run.yaml``
of its run); ``--force`` uses it anyway. Torch files are read as weights only: one that needs more
(it could run code) is refused unless the user passes ``--trust_checkpoint``.
"""

from __future__ import annotations

import contextlib
import os
import re
import shlex
import sys
import zipfile
from collections.abc import Iterator
from typing import Any

import gymnasium as gym

from simlab.cli.runs import CHECKPOINT_LAYOUT, find_run_info, is_checkpoint_name
from simlab.rl.utils import is_multi_agent
from simlab.utils.errors import CheckpointError, CheckpointNotFoundError, SimlabError, UntrustedFileError, describe
from simlab.utils.io import remove_stale_temp_files
from simlab.utils.trust import is_torchscript, torch_load

__all__ = [
    "check_checkpoint_sizes",
    "check_checkpoint_source",
    "checkpoint_library",
    "checkpoint_load_errors",
    "layer_mismatch",
    "env_sizes",
    "find_last_checkpoint",
    "note_missing_env_overrides",
    "override_key",
    "read_checkpoint",
    "resolve_checkpoint",
]


def _natural_key(name: str) -> list:
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", name)]


def read_checkpoint(path: str, trust: bool = False) -> Any:
    """Open ``path`` as its library would, weights only unless ``trust``; a :class:`CheckpointError`
    says why it cannot be read (:class:`UntrustedFileError`: it needs more than weights).

    Returns the loaded object (a dict for torch checkpoints, the zip's member names for SB3).
    """
    if not os.path.isfile(path):
        raise CheckpointNotFoundError(f"Checkpoint '{path}' does not exist.")
    if os.path.getsize(path) == 0:
        raise CheckpointError(f"Checkpoint '{path}' is empty (0 bytes): its write was cut off.")
    if path.endswith(".zip"):
        try:
            with zipfile.ZipFile(path) as z:
                bad = z.testzip()
                names = z.namelist()
        except (zipfile.BadZipFile, OSError, EOFError) as e:
            raise CheckpointError(f"Checkpoint '{path}' is not a complete zip archive ({e}).") from e
        if bad is not None or "policy.pth" not in names:
            raise CheckpointError(f"Checkpoint '{path}' is damaged or not a Stable-Baselines3 model.")
        return names
    exported = _exported_format(path)
    if exported:
        raise CheckpointError(
            f"Checkpoint '{path}' is an exported {exported} policy (what play writes to exported/), not a training"
            " checkpoint; pass the run's checkpoint (model_<N>.pt, agent_<N>.pt, ...) or its run folder."
        )
    try:
        return torch_load(path, map_location="cpu", trust=trust)
    except UntrustedFileError:
        raise
    except Exception as e:  # noqa: BLE001 - whatever torch/pickle raise, the file cannot be used
        raise CheckpointError(  # corrupt bytes make pickle raise anything, a MemoryError with no message too
            f"Checkpoint '{path}' cannot be read ({describe(e)}): it is truncated, corrupt or not a torch checkpoint."
        ) from e


def _exported_format(path: str) -> str | None:
    """The format of a policy ``simlab play`` exported (ONNX, TorchScript), else None (torch.load's refusal of
    them reads as a corrupt file and advises an unsafe load)."""
    if path.endswith(".onnx"):
        return "ONNX"
    return "TorchScript" if is_torchscript(path) else None


def checkpoint_library(loaded: Any) -> str | None:
    """The library that wrote a checkpoint (from :func:`read_checkpoint`'s result), None if unsure."""
    if isinstance(loaded, list):
        return "sb3"
    if not isinstance(loaded, dict):
        return None
    if "iter" in loaded and any(k.endswith("_state_dict") for k in loaded):
        return "rsl_rl"
    if "model" in loaded and "epoch" in loaded:
        return "rl_games"
    if "state_dict" in loaded and "terms" in loaded:
        return "bc"  # simlab.rl.bc.save_bc_policy
    if "policy" in loaded or all(isinstance(v, dict) and "policy" in v for v in loaded.values()):
        return "skrl"  # PPO: {"policy": ..., "value": ...}; IPPO / MAPPO: {agent: {"policy": ...}}
    return None


def _candidates(run_dirs: list[str], library: str) -> Iterator[str]:
    """Checkpoint files of ``run_dirs`` (given newest first), newest first within each run."""
    for run in run_dirs:
        folder = os.path.join(run, *CHECKPOINT_LAYOUT[library][0])
        if not os.path.isdir(folder):
            continue
        remove_stale_temp_files(folder)  # of a save that was killed mid-write
        names = [f for f in os.listdir(folder) if is_checkpoint_name(f, library)]
        names = [f for f in names if os.path.isfile(os.path.join(folder, f))]
        for name in sorted(names, key=_natural_key, reverse=True):
            yield os.path.join(folder, name)


def _first_readable(candidates: Iterator[str], where: str, trust: bool = False) -> str:
    skipped: list[str] = []
    for path in candidates:
        try:
            read_checkpoint(path, trust)
        except UntrustedFileError:
            raise  # not a torn file to skip: the user decides
        except CheckpointError as e:
            skipped.append(str(e))
            continue
        for reason in skipped:
            print(f"[simlab] WARNING: skipped an unreadable checkpoint: {reason}", file=sys.stderr)
        if skipped:
            print(f"[simlab] WARNING: using '{path}' instead.", file=sys.stderr)
        return os.path.abspath(path)
    if skipped:
        raise CheckpointError(f"No readable checkpoint in {where}: " + " ".join(skipped))
    raise CheckpointNotFoundError(f"No checkpoint in {where}.")


def find_last_checkpoint(log_root: str, library: str, experiment: str, trust: bool = False, task: str = "...") -> str:
    """The newest readable checkpoint of the newest run of ``experiment`` that has one."""
    log_path = os.path.abspath(os.path.join(log_root, library, experiment))
    hint = f"Train first (simlab train --task {task} --library {library}) or pass --checkpoint PATH."
    if not os.path.isdir(log_path):
        raise CheckpointNotFoundError(
            f"No checkpoint of '{experiment}' trained with {library}: the folder '{log_path}' does not exist. {hint}"
        )
    runs = sorted((e.path for e in os.scandir(log_path) if e.is_dir()), key=_natural_key, reverse=True)
    try:
        return _first_readable(_candidates(runs, library), f"the runs of '{log_path}'", trust)
    except CheckpointNotFoundError as e:
        raise CheckpointNotFoundError(f"No checkpoint of '{experiment}' trained with {library}: {e} {hint}") from e


def resolve_checkpoint(path: str, library: str, trust: bool = False) -> str:
    """``path`` if it is a readable checkpoint file; for a run folder, its newest readable checkpoint."""
    if os.path.isfile(path):
        read_checkpoint(path, trust)
        return os.path.abspath(path)
    if os.path.isdir(path):
        try:
            return _first_readable(_candidates([os.path.abspath(path)], library), f"the run folder '{path}'", trust)
        except CheckpointNotFoundError:
            # an experiment's folder (Isaac Lab's logs/<library>/<experiment>) holds runs: name the newest
            runs = sorted((e.path for e in os.scandir(path) if e.is_dir()), key=_natural_key, reverse=True)
            newest = next((run for run in runs if next(_candidates([run], library), None)), None)
            if newest is None:
                raise
            raise CheckpointNotFoundError(
                f"'{path}' holds run folders, not checkpoints; pass one of them (the newest with a checkpoint:"
                f" '{newest}')."
            ) from None
    raise CheckpointNotFoundError(f"Checkpoint '{path}' does not exist (looked at '{os.path.abspath(path)}').")


def env_sizes(env: gym.Env) -> dict[str, Any]:
    """The observation and action sizes a policy of ``env`` sees: ``{"observations": {...}, "actions": ...}``."""
    base = env.unwrapped
    if is_multi_agent(base):
        agents = list(base.possible_agents)
        return {
            "observations": {a: int(gym.spaces.flatdim(base.observation_spaces[a])) for a in agents},
            "actions": {a: int(gym.spaces.flatdim(base.action_spaces[a])) for a in agents},
        }
    groups = base.single_observation_space
    return {
        "observations": {k: int(gym.spaces.flatdim(v)) for k, v in groups.spaces.items()},
        "actions": int(gym.spaces.flatdim(base.single_action_space)),
    }


def check_checkpoint_source(
    checkpoint: str, library: str, task: str | None, force: bool = False, trust: bool = False
) -> None:
    """Refuse (``CheckpointError``) a checkpoint written by another library or trained on another task.

    The library is read from the file's contents, the task from its run's ``params/run.yaml``; ``task``
    None accepts any task (``--init_weights`` fine-tunes another task's weights). ``force`` turns the
    refusal into a warning.
    """
    problems: list[str] = []
    written_by = checkpoint_library(read_checkpoint(checkpoint, trust))
    if written_by is not None and written_by != library:
        problems.append(f"it was written by {written_by}, not {library} (use --library {written_by})")
    info = find_run_info(checkpoint) or {}
    if written_by is None and info.get("library") not in (None, library):
        problems.append(f"its run was trained with {info['library']}, not {library}")
    # a task's -Play variant plays what the task trained (Isaac Lab's train-then-play workflow)
    if task is not None and info.get("task") not in (None, task, task.replace("-Play", "")):
        problems.append(f"its run trained the task '{info['task']}', not '{task}' (use --task {info['task']})")
    _refuse(checkpoint, problems, force)


def check_checkpoint_sizes(checkpoint: str, sizes: dict[str, Any], force: bool = False) -> None:
    """Refuse a checkpoint whose run had other observation or action sizes than :func:`env_sizes` ``sizes``."""
    info = find_run_info(checkpoint) or {}
    problems = [
        f"its {what} sizes are {info[what]}; this env's are {sizes[what]}"
        for what in ("observations", "actions")
        if what in info and info[what] != sizes[what]
    ]
    if problems and info.get("env_overrides"):
        problems.append(f"its run was trained with {shlex.join(info['env_overrides'])}: give this command the same")
    if problems and info.get("algorithm") in ("IPPO", "MAPPO"):  # one policy per agent, not PPO's one for all
        problems.append(f"its run trained skrl's {info['algorithm']}: give --algorithm {info['algorithm']}")
    _refuse(checkpoint, problems, force)


def override_key(text: str) -> str:
    """The config key an override sets (``+env.x=1`` -> ``env.x``)."""
    return text.split("=", 1)[0].lstrip("+~")


RUN_SETTINGS = ("env.scene.num_envs", "env.seed")
"""Env overrides that set how a run ran, not the env a policy learned (play has --num_envs and --seed)."""


def note_missing_env_overrides(checkpoint: str, overrides: list[str]) -> list[str]:
    """Print (and return) the env overrides the checkpoint's run was trained with that ``overrides`` does
    not set: a tracking policy trained on another clip fits the default one in size, and played it silently."""
    given = {override_key(o) for o in overrides} | set(RUN_SETTINGS)
    trained = (find_run_info(checkpoint) or {}).get("env_overrides", [])
    missing = [o for o in trained if override_key(o) not in given]
    if missing:
        print(
            f"[simlab] Its run was trained with {shlex.join(missing)}, which this command does not give:"
            " add it to play the env the policy learned in."
        )
    return missing


def _refuse(checkpoint: str, problems: list[str], force: bool) -> None:
    if not problems:
        return
    text = f"Checkpoint '{checkpoint}' does not fit: " + "; ".join(problems) + "."
    if force:
        print(f"[simlab] WARNING (--force): {text}", file=sys.stderr)
        return
    raise CheckpointError(f"{text} Nothing was loaded or written. Pass --force to use it anyway.")


# what torch's load_state_dict says of the first layer whose shape differs (then one line per other layer)
_SIZE_MISMATCH = re.compile(
    r"size mismatch for ([\w.]+): copying a param with shape torch\.Size\(\[([\d, ]*)\]\) from checkpoint, "
    r"the shape in current model is torch\.Size\(\[([\d, ]*)\]\)"
)
_KEY_MISMATCH = re.compile(r"(Missing|Unexpected) key\(s\) in state_dict: ([^\n]*)")


def layer_mismatch(checkpoint: str, task: str, layer: str, in_checkpoint: str, here: str) -> str:
    """One line: ``checkpoint``'s ``layer`` has another size than the policy of ``task`` has."""
    return (
        f"Checkpoint '{checkpoint}' does not fit {task}: its layer '{layer}' has the size [{in_checkpoint}], "
        f"this task's policy [{here}] (a checkpoint of another task, or trained with other env overrides?)."
    )


def _load_error_line(checkpoint: str, library: str, task: str, error: BaseException) -> str | None:
    """The one line that says why a library could not load ``checkpoint``'s state dicts, or None."""
    text = str(error)
    if m := _SIZE_MISMATCH.search(text):
        return layer_mismatch(checkpoint, task, m[1], m[2], m[3])
    if m := _KEY_MISMATCH.search(text):
        keys = [k.strip('" ') for k in m[2].rstrip(". ").split(",")]
        shown = ", ".join(keys[:3]) + (f" and {len(keys) - 3} more" if len(keys) > 3 else "")
        return f"Checkpoint '{checkpoint}' does not fit a {library} policy of {task}: {m[1].lower()} layers {shown}."
    return None


@contextlib.contextmanager
def checkpoint_load_errors(
    checkpoint: str | None, library: str, task: str, only_state_dicts: bool = False
) -> Iterator[None]:
    """Turn a library's failure to load ``checkpoint`` into one line (a :class:`CheckpointError`): the
    first layer of another size, with both sizes, instead of torch's list of every layer. With
    ``only_state_dicts`` (a training block) other errors pass through unchanged."""
    try:
        yield
    except SimlabError:
        raise
    except (RuntimeError, KeyError, ValueError, TypeError) as e:
        if checkpoint is None:
            raise
        line = _load_error_line(checkpoint, library, task, e)
        if line is None:
            if only_state_dicts:
                raise
            line = f"Cannot load '{checkpoint}' as a {library} policy of {task}: {describe(e)}."
        raise CheckpointError(f"{line} Nothing was loaded.") from e
