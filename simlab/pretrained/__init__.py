"""Policies trained here and shipped with simlab: ``simlab play --use_pretrained_checkpoint``.

Each is a run folder, ``simlab/pretrained/<task name>/<library>/``: ``params/`` as ``simlab train``
writes it less the resolved env config (``env.yaml``: the task and the command rebuild it; the record
lists the observation terms the policy reads), the policy's weights in one file, ``policy.pt``
(:mod:`simlab.pretrained.weights`; play turns it back into the library's checkpoint in the user's log
folder and exports it there), and its record: ``record.json`` (how ``scripts/make_pretrained.py``
made it: commands, seed, iterations, the task's criterion and the
value the policy reached on the CPU; :func:`pretrained_record`; the env overrides it was trained
with, which play applies: :func:`pretrained_env_overrides`; the agent config it was made with, which
play loads it with: :func:`pretrained_agent`), or ``record.txt`` for the first
cartpoles.
"""

from __future__ import annotations

import json
import os
import shutil
from typing import Any

__all__ = [
    "POLICY_FILE",
    "PRETRAINED_DIR",
    "copy_pretrained_run",
    "list_pretrained",
    "pretrained_agent",
    "pretrained_env_overrides",
    "pretrained_libraries",
    "pretrained_record",
    "pretrained_run_dir",
    "unpack_pretrained_checkpoint",
]

PRETRAINED_DIR = os.path.dirname(os.path.abspath(__file__))
POLICY_FILE = "policy.pt"  # the stored weights in each shipped run folder


def _task_folder(task: str) -> str:
    # a task's -Play variant plays the policy trained on the task itself (Isaac Lab's play.py rule)
    return task.split("/")[-1].replace("-Play", "")


def list_pretrained() -> list[tuple[str, str]]:
    """The shipped ``(task, library)`` pairs."""
    pairs = []
    for task in sorted(os.listdir(PRETRAINED_DIR)):
        folder = os.path.join(PRETRAINED_DIR, task)
        if os.path.isdir(folder) and not task.startswith("__"):
            pairs += [(f"simlab/{task}", lib) for lib in sorted(os.listdir(folder))]
    return pairs


def pretrained_libraries(task: str) -> list[str]:
    """The libraries of the policies shipped for ``task`` (its ``-Play`` variant: the task's own), sorted."""
    return [lib for t, lib in list_pretrained() if t == f"simlab/{_task_folder(task)}"]


def pretrained_run_dir(task: str, library: str) -> str:
    """The shipped run folder of ``task`` trained with ``library``; a clear error lists what is shipped."""
    folder = os.path.join(PRETRAINED_DIR, _task_folder(task), library)
    if not os.path.isdir(folder):
        own = pretrained_libraries(task)
        if own:  # the task ships one for another library: the flag to add, not every shipped policy
            raise FileNotFoundError(
                f"No pretrained {library} policy for {task}. Shipped for it: {', '.join(own)}"
                f" (simlab play --library {own[0]})."
            )
        shipped = ", ".join(f"{t} ({lib})" for t, lib in list_pretrained()) or "none"
        raise FileNotFoundError(
            f"No pretrained {library} policy for {task}. Shipped: {shipped}. "
            f"Train one with: simlab train --task {task} --library {library} --headless"
        )
    return folder


def pretrained_record(task: str, library: str) -> dict[str, Any] | None:
    """The ``record.json`` of the shipped run (None for a run shipped before records were JSON)."""
    path = os.path.join(pretrained_run_dir(task, library), "record.json")
    if not os.path.isfile(path):
        return None
    with open(path) as f:
        return json.load(f)


def pretrained_env_overrides(task: str, library: str) -> list[str]:
    """The ``env.*`` overrides the shipped policy was trained with (e.g. ``env.frame_stack=2``, which
    changes its observation): play applies them before the user's own."""
    record = pretrained_record(task, library)
    return list(record.get("env_overrides", [])) if record else []


def pretrained_agent(task: str, library: str) -> str | None:
    """The agent config the shipped policy was made with (its registry key, e.g. a distilled student's
    ``rsl_rl_distillation_cfg_entry_point``), None for the library's default: play loads it with that one."""
    record = pretrained_record(task, library)
    return record.get("agent") if record else None


def copy_pretrained_run(task: str, library: str, log_root: str) -> str:
    """Copy the shipped run into ``<log_root>/pretrained/<library>/<task name>`` (where play writes its
    exports and videos; outside the training runs, so ``--use_last_checkpoint`` never picks it), with
    its ``policy.pt`` written out as the library's checkpoint, and return that folder."""
    return _unpack(task, library, log_root)[0]


def unpack_pretrained_checkpoint(task: str, library: str, log_root: str) -> str:
    """:func:`copy_pretrained_run`, returning the checkpoint file it wrote: the shipped policy, never
    another file someone put in that folder of the log root."""
    return _unpack(task, library, log_root)[1]


def _unpack(task: str, library: str, log_root: str) -> tuple[str, str]:
    from simlab.pretrained.weights import unpack_policy, write_checkpoint

    source = pretrained_run_dir(task, library)
    target = os.path.abspath(os.path.join(log_root, "pretrained", library, _task_folder(task)))
    shutil.copytree(source, target, dirs_exist_ok=True, ignore=shutil.ignore_patterns(POLICY_FILE))
    name, checkpoint = unpack_policy(os.path.join(source, POLICY_FILE))
    path = os.path.join(target, name)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    write_checkpoint(checkpoint, path, library)
    return target, path
