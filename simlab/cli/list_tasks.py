"""``simlab list``: the registered tasks and the libraries each has agent configs for."""

from __future__ import annotations

import gymnasium as gym

from simlab.tasks.utils import registered_task_ids

__all__ = ["list_tasks"]


def list_tasks(keyword: str | None = None) -> int:
    ids = registered_task_ids(keyword)
    if not ids:
        print(f"No task matches '{keyword}'. All tasks: {registered_task_ids()}")
        return 1
    width = max(len(i) for i in ids)
    print(f"{'task'.ljust(width)}  agent configs")
    for task in ids:
        keys = [k.removesuffix("_cfg_entry_point") for k in gym.spec(task).kwargs if k.endswith("_cfg_entry_point")]
        print(f"{task.ljust(width)}  {', '.join(k for k in keys if k != 'env')}")
    return 0
