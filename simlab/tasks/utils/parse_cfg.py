"""Configs from the Gymnasium registry and checkpoints from log folders (Isaac Lab's ``parse_cfg``)."""

from __future__ import annotations

import importlib
import inspect
import os
import re
from collections.abc import Sequence
from typing import Any

import gymnasium as gym
import yaml

from simlab.utils.errors import ConfigError
from simlab.utils.io import ConfigYamlLoader
from simlab.utils.string import closest_matches, simlab_task_id

__all__ = [
    "get_checkpoint_path",
    "load_cfg_from_registry",
    "parse_env_cfg",
    "registered_task_ids",
    "registry_kwargs",
    "simlab_task_id",
    "split_presets",
]


def registered_task_ids(keyword: str | None = None) -> list[str]:
    """The simlab task ids (sorted), optionally only those containing ``keyword`` (case-insensitive)."""
    import simlab.tasks  # noqa: F401 - registers the tasks

    ids = sorted(i for i in gym.registry if i.startswith("simlab/"))
    if keyword:
        ids = [i for i in ids if keyword.lower() in i.lower()]
    return ids


def task_spec(task_name: str) -> gym.envs.registration.EnvSpec:
    """The registry entry of ``task_name``; an unknown id raises naming the closest registered ones."""
    import simlab.tasks  # noqa: F401

    if not isinstance(task_name, str) or not task_name:
        raise ConfigError(f"A task id is required, e.g. 'simlab/Cartpole-v0'; got {task_name!r}.")
    name = task_name.split(":")[-1]
    if name.startswith("simlab/") and name not in gym.registry and simlab_task_id(name) in gym.registry:
        name = simlab_task_id(name)  # an id without its version (Isaac Lab 3.0's form): the highest one
    if name not in gym.registry:
        ids = registered_task_ids()
        close = closest_matches(name, ids, n=3, cutoff=0.3)
        hint = f" Closest: {close}." if close else ""
        simlab_id = simlab_task_id(name)
        if simlab_id != name and simlab_id in ids:
            hint = f" That is Isaac Lab's id; simlab's is '{simlab_id}' (scripts/reinforcement_learning/ takes either)."
        # the closest ids and where to see the rest: all of them made a line of thousands of characters
        raise ConfigError(
            f"Unknown task '{task_name}'.{hint} {len(ids)} tasks are registered: "
            "`simlab list` shows them, `simlab list WORD` those whose id contains WORD; the Isaac Lab tasks"
            " simlab lacks, and why, are in docs/task_families.md."
        )
    return gym.spec(name)


def _load_entry_point(entry_point: Any, what: str) -> Any:
    if callable(entry_point):
        return entry_point() if inspect.isclass(entry_point) or inspect.isfunction(entry_point) else entry_point
    if not isinstance(entry_point, str):
        return entry_point  # an instance given directly
    module_name, _, attr = entry_point.partition(":")
    if attr.endswith((".yaml", ".yml")):
        module = importlib.import_module(module_name)
        path = os.path.join(os.path.dirname(module.__file__), attr)
        if not os.path.isfile(path):
            raise FileNotFoundError(f"{what}: the file '{path}' does not exist.")
        with open(path) as f:
            return yaml.load(f, Loader=ConfigYamlLoader) or {}  # noqa: S506 - safe, plus tuples
    if entry_point.endswith((".yaml", ".yml")):
        with open(entry_point) as f:
            return yaml.load(f, Loader=ConfigYamlLoader) or {}  # noqa: S506 - safe, plus tuples
    if not attr:
        raise ValueError(f"{what}: expected 'module:ClassName' or 'module:file.yaml', got '{entry_point}'.")
    obj: Any = importlib.import_module(module_name)
    for part in attr.split("."):
        obj = getattr(obj, part)
    return obj() if callable(obj) else obj


def registry_kwargs(task_name: str, presets: Sequence[str] = ()) -> dict[str, Any]:
    """The registration kwargs of ``task_name`` with the entry points of the named ``presets`` in place.

    A task registers its variants (Isaac Lab 3.0's ``presets=``) as ``kwargs["presets"]``: a dict from
    a preset name to the entry points it replaces, e.g. ``{"depth": {"env_cfg_entry_point": "m:DepthCfg"}}``.
    Presets apply in the order given; an unknown name is a ConfigError naming the task's presets.
    """
    spec = task_spec(task_name)
    kwargs = dict(spec.kwargs)
    table = kwargs.get("presets") or {}
    for name in presets:
        if name not in table:
            have = f"its presets are {', '.join(sorted(table))}" if table else "it registers no presets"
            raise ConfigError(f"presets={name}: not a preset of {task_name} ({have}).")
        kwargs.update(table[name])
    return kwargs


def split_presets(task_name: str, names: Sequence[str]) -> tuple[list[str], list[str], list[str]]:
    """``(registered, in_config, table)``: the ``presets=`` names the task registers (its variants'
    entry points, :func:`registry_kwargs`), the others (alternatives of the ``PresetCfg`` slots inside
    its configs, :mod:`simlab.tasks.utils.presets`), and every name the task registers."""
    table = sorted(task_spec(task_name).kwargs.get("presets") or {})
    return [n for n in names if n in table], [n for n in names if n not in table], table


def load_cfg_from_registry(task_name: str, entry_point_key: str, presets: Sequence[str] = ()) -> Any:
    """Load the config that the task registered under ``entry_point_key`` (with the entry points of the
    named ``presets``, see :func:`registry_kwargs`).

    Config classes are instantiated; ``"module:file.yaml"`` entry points are read into a dict.
    E.g. ``load_cfg_from_registry("simlab/Cartpole-v0", "rsl_rl_cfg_entry_point")``.
    """
    kwargs = registry_kwargs(task_name, presets)
    entry_point = kwargs.get(entry_point_key)
    if entry_point is None:
        keys = sorted(k for k in kwargs if k.endswith("entry_point"))
        close = closest_matches(entry_point_key, keys, n=1)
        hint = f" Did you mean '{close[0]}'?" if close else ""
        raise ConfigError(f"Task '{task_name}' has no '{entry_point_key}'.{hint} It registers: {keys}.")
    return _load_entry_point(entry_point, f"{task_name} {entry_point_key}")


def parse_env_cfg(
    task_name: str,
    device: str = "cuda:0",
    num_envs: int | None = None,
    use_fabric: bool | None = None,
    overrides: Sequence[str] | None = None,
) -> Any:
    """The task's env config with the simulation ``device`` and, if given, ``num_envs`` set.

    ``overrides`` are Isaac Lab 3.0's trailing words: ``presets=a,b`` (the task's registered variants,
    :func:`registry_kwargs`; a physics backend name among them acts as ``physics=``), ``physics=NAME``
    (:func:`simlab.sim.backend_names.engine_for`) and Hydra-style field overrides (``scene.num_envs=8``
    or ``env.scene.num_envs=8``). ``use_fabric`` is accepted for Isaac Lab compatibility and ignored
    (simlab has no USD stage).
    """
    from simlab.sim.backend_names import PHYSICS, engine_for
    from simlab.tasks.utils.presets import select_presets
    from simlab.utils.device import resolve_device

    presets: list[str] = []
    engine = physics = None
    fields = []
    for word in overrides or ():
        key, _, value = word.partition("=")
        if key == "presets":
            for name in value.split(","):
                if name in PHYSICS:
                    engine, physics = engine_for(name), name
                else:
                    presets.append(name)
        elif key == "physics":
            engine, physics = engine_for(value), value
        else:
            bare = word.lstrip("+~")  # Hydra's + (add) and ~ (delete) prefixes stay in front
            fields.append(word if bare.startswith("env.") else f"{word[: len(word) - len(bare)]}env.{bare}")
    registered, in_config, table = split_presets(task_name, presets)
    cfg = load_cfg_from_registry(task_name, "env_cfg_entry_point", registered)
    if not isinstance(cfg, dict):
        cfg, _, fields = select_presets(cfg, None, in_config, physics, fields, table, task_name)
    if fields:
        from simlab.tasks.utils.hydra import apply_overrides

        apply_overrides(cfg, None, fields)
    if engine is not None:
        cfg.sim.engine = engine
    if isinstance(cfg, dict):
        raise TypeError(f"The env config of '{task_name}' must be a config class, not a dict.")
    cfg.sim.device = resolve_device(device)
    if num_envs is not None:
        if isinstance(num_envs, bool) or not isinstance(num_envs, int) or num_envs < 1:
            raise ValueError(f"num_envs must be a positive int, got {num_envs!r}.")
        cfg.scene.num_envs = num_envs
    return cfg


def _natural_key(name: str) -> list:
    # model_100.pt after model_99.pt
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", name)]


def get_checkpoint_path(
    log_path: str,
    run_dir: str = ".*",
    checkpoint: str = ".*",
    other_dirs: list[str] | None = None,
    sort_alphabetical: bool = True,
) -> str:
    """The latest checkpoint in the latest run under ``log_path``.

    Args:
        log_path: the experiment folder, e.g. ``logs/rsl_rl/cartpole``.
        run_dir: regex for the run folders (the last one, by name = time stamp, is taken).
        checkpoint: regex for the checkpoint files (the last one in natural order is taken).
        other_dirs: sub-folders of the run that hold the checkpoints, e.g. ``["checkpoints"]``.
        sort_alphabetical: sort runs by name (time stamps); False sorts by modification time.

    Raises:
        FileNotFoundError: naming the folders looked in and the patterns used.
    """
    if not os.path.isdir(log_path):
        raise FileNotFoundError(f"No runs: the folder '{os.path.abspath(log_path)}' does not exist.")
    runs = [e for e in os.scandir(log_path) if e.is_dir() and re.match(run_dir, e.name)]
    if not runs:
        raise FileNotFoundError(f"No run folder matching '{run_dir}' in '{os.path.abspath(log_path)}'.")
    if sort_alphabetical:
        runs.sort(key=lambda e: e.name)
    else:
        runs.sort(key=lambda e: e.stat().st_mtime)
    looked = []
    # the latest run first; fall back to earlier runs that have checkpoints (a run may have died early)
    for run in reversed(runs):
        folder = os.path.join(run.path, *(other_dirs or []))
        looked.append(folder)
        if not os.path.isdir(folder):
            continue
        files = [f for f in os.listdir(folder) if re.match(checkpoint, f) and os.path.isfile(os.path.join(folder, f))]
        if files:
            files.sort(key=_natural_key)
            return os.path.join(folder, files[-1])
        if run_dir != ".*":
            break
    raise FileNotFoundError(
        f"No checkpoint matching '{checkpoint}' found. Looked in: {[os.path.abspath(p) for p in looked]}."
    )
