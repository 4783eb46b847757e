"""``simlab list``: the registered tasks and the libraries each has agent configs for."""

from __future__ import annotations

import re

import gymnasium as gym

from simlab.tasks.utils import registered_task_ids
from simlab.utils.string import closest_matches

__all__ = ["list_tasks"]


def list_tasks(keyword: str | None = None) -> int:
    ids = registered_task_ids(keyword)
    if not ids:
        # the words of the ids closest to the keyword, not every id in one line
        every = registered_task_ids()
        words = sorted({w.lower() for i in every for w in re.split(r"[/-]", i)})
        close = closest_matches(str(keyword).lower(), words, n=3, cutoff=0.3)
        hint = f" Close words in the ids: {close}." if close else ""
        print(f"No task id contains '{keyword}'.{hint} `simlab list` shows all {len(every)} tasks.")
        return 1
    width = max(len(i) for i in ids)
    print(f"{'task'.ljust(width)}  agent configs")
    for task in ids:
        keys = [k.removesuffix("_cfg_entry_point") for k in gym.spec(task).kwargs if k.endswith("_cfg_entry_point")]
        print(f"{task.ljust(width)}  {', '.join(k for k in keys if k != 'env')}")
    return 0
