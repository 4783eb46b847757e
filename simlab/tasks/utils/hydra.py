"""Command-line overrides of the env and agent configs on hydra-core (Isaac Lab's
``isaaclab_tasks.utils.hydra``).

``env.actions.joint_effort.scale=10 agent.seed=2024 env.rewards.alive=null +agent.params.x=1``:

* Hydra's override grammar reads each word: ``10`` int, ``0.5`` / ``1e9`` float, ``true``, ``[1, 2]``,
  ``{a: 1}``, ``null``, quoted strings, ``${env.sim.dt}`` interpolations; ``+key=value`` adds a dict
  key, ``~key`` removes a term (as ``key=null`` does);
* the configs are stored in Hydra's ``ConfigStore`` as plain dicts (``register_task_to_hydra``) and
  Hydra composes the overrides onto them; the composed values are then written into the config
  classes, so callables (``"module:name"``), slices (``"slice(0,3,None)"``) and tuples come back as
  what the field holds;
* a key that does not exist is an error naming the nearest valid keys; a number field takes only
  numbers, a bool field only booleans.

Composition uses ``hydra.compose``: unlike ``@hydra.main`` it never changes the working directory
nor writes ``outputs/``.
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
import sys
from collections.abc import Callable, Sequence
from typing import Any

from simlab.utils.dict import MISSING_STR, class_to_dict, replace_strings_with_slices, update_class_from_dict
from simlab.utils.errors import ConfigError
from simlab.utils.string import callable_modules, closest_matches

__all__ = ["OverrideError", "apply_overrides", "hydra_task_config", "parse_override", "register_task_to_hydra"]

_ROOTS = ("env", "agent")
_store_ids = itertools.count()


class OverrideError(ConfigError):
    """A command-line override that names a wrong key or gives a wrong value."""


# -- Hydra's side: parsing, the config store, composition ------------------------------------------


def _parse(overrides: Sequence[str]) -> list:
    """Hydra's ``Override`` objects for ``overrides``; each must be a key=value (or ~key) word."""
    try:
        from hydra.core.override_parser.overrides_parser import OverridesParser
        from hydra.errors import OverrideParseException
    except ImportError as err:
        raise OverrideError(
            'Overrides are read by hydra-core, which is not installed: pip install "simlab[train]".'
        ) from err

    for text in overrides:
        if "=" not in text and not text.startswith("~"):
            raise OverrideError(
                f"'{text}' is not an override. Use key=value, e.g. env.scene.num_envs=32 or agent.seed=1."
            )
    try:
        parsed = OverridesParser.create().parse_overrides(list(overrides))
    except OverrideParseException as err:
        raise OverrideError(
            str(err).splitlines()[0] + " (Hydra's override grammar: hydra.cc/docs/advanced/override_grammar/basic)"
        ) from err
    for override in parsed:
        if override.is_sweep_override():
            raise OverrideError(f"'{override.input_line}': sweeps (a,b or range()) need a multirun; give one value.")
    return parsed


def parse_override(text: str) -> tuple[list[str], Any, bool]:
    """``"env.a.b=1"`` -> (``["env", "a", "b"]``, ``1``, add); ``add`` is True for ``+key=value``."""
    override = _parse([text])[0]
    path = override.key_or_group.split(".")
    _check_root(text, path)
    return path, None if override.is_delete() else override.value(), override.is_add()


def _plain(cfg: Any) -> Any:
    """A config as the plain nested dict Hydra stores (MISSING as Hydra's ``???``)."""

    def fix(value: Any) -> Any:
        if value is dataclasses.MISSING:
            return MISSING_STR
        if isinstance(value, dict):
            return {k: fix(v) for k, v in value.items()}
        if isinstance(value, (list, tuple)):
            return [fix(v) for v in value]
        if hasattr(value, "tolist"):  # tensors in a config
            return value.tolist()
        return value

    if cfg is None:
        return None
    return fix(class_to_dict(cfg) if not isinstance(cfg, dict) else class_to_dict(dict(cfg)))


def _store(name: str, env_cfg: Any, agent_cfg: Any) -> None:
    from hydra.core.config_store import ConfigStore

    group, _, base = name.rpartition("/")  # "simlab/Cartpole-v0": config "Cartpole-v0" of group "simlab"
    node = {"env": _plain(env_cfg), "agent": _plain(agent_cfg)}
    # the global package: composing "simlab/Cartpole-v0" gives {"env", "agent"} at the root, as Isaac Lab's ids do
    ConfigStore.instance().store(name=base, node=node, group=group or None, package="_global_")


def _compose(name: str, overrides: list[str]):
    from hydra import compose, initialize
    from hydra.core.global_hydra import GlobalHydra
    from hydra.errors import HydraException
    from omegaconf.errors import OmegaConfBaseException

    try:
        if GlobalHydra.instance().is_initialized():  # inside a @hydra.main or an initialize() block
            return compose(config_name=name, overrides=overrides)
        with initialize(version_base="1.3", config_path=None):
            return compose(config_name=name, overrides=overrides)
    except (HydraException, OmegaConfBaseException) as err:
        raise OverrideError(f"Hydra could not apply the overrides: {str(err).strip()}") from err


def register_task_to_hydra(task_name: str, agent_cfg_entry_point: str | None) -> tuple[Any, Any]:
    """Load the env and agent configs of ``task_name`` and store them in Hydra's ``ConfigStore``
    under the task's name (``{"env": ..., "agent": ...}``); returns the two config objects."""
    from .parse_cfg import load_cfg_from_registry

    env_cfg = load_cfg_from_registry(task_name, "env_cfg_entry_point")
    agent_cfg = load_cfg_from_registry(task_name, agent_cfg_entry_point) if agent_cfg_entry_point else None
    _store(task_name, env_cfg, agent_cfg)
    return env_cfg, agent_cfg


# -- simlab's side: checking keys and values, writing into the config classes --------------------


def _check_root(text: str, path: list[str]) -> None:
    if path[0] not in _ROOTS:
        close = closest_matches(path[0], _ROOTS, n=1)
        hint = f" Did you mean '{close[0]}.{'.'.join(path[1:])}'?" if close else ""
        raise OverrideError(f"'{text}': overrides start with 'env.' or 'agent.', not '{path[0]}.'.{hint}")
    if len(path) < 2:
        raise OverrideError(f"'{text}': name a field inside '{path[0]}', e.g. {path[0]}.seed=1.")


def _keys(obj: Any) -> list[str]:
    if isinstance(obj, dict):
        return [str(k) for k in obj]
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return [f.name for f in dataclasses.fields(obj)]
    return [k for k in vars(obj) if not k.startswith("_")] if hasattr(obj, "__dict__") else []


def _get(obj: Any, key: str) -> Any:
    return obj[key] if isinstance(obj, dict) else getattr(obj, key)


def _unknown_key(text: str, dotted: str, key: str, obj: Any) -> OverrideError:
    valid = _keys(obj)
    close = closest_matches(key, valid, n=3, cutoff=0.4)
    hint = f" Nearest valid keys: {close}." if close else ""
    return OverrideError(f"'{text}': '{dotted}' has no key '{key}'.{hint} Valid keys: {valid}.")


def _parent(text: str, path: list[str], roots: dict[str, Any], add: bool) -> Any:
    """The object holding the last key of ``path`` (new dict levels are made for ``+`` adds)."""
    obj = roots[path[0]]
    if obj is None:
        raise OverrideError(f"'{text}': there is no {path[0]} config to override.")
    for i, key in enumerate(path[1:-1], start=1):
        if key not in _keys(obj):
            if not (add and isinstance(obj, dict)):
                raise _unknown_key(text, ".".join(path[:i]), key, obj)
            obj[key] = {}
        obj = _get(obj, key)
        if obj is None:
            raise OverrideError(f"'{text}': '{'.'.join(path[: i + 1])}' is None (removed); cannot set inside it.")
    if path[-1] not in _keys(obj) and not (add and isinstance(obj, dict)):
        raise _unknown_key(text, ".".join(path[:-1]), path[-1], obj)
    return obj


def _declared_type(obj: Any, key: str) -> str | None:
    """The annotation of config field ``key`` as written (``"int"``, ``"float | None"``), None for dicts."""
    if not dataclasses.is_dataclass(obj):
        return None
    for f in dataclasses.fields(obj):
        if f.name == key:
            return f.type if isinstance(f.type, str) else getattr(f.type, "__name__", str(f.type))
    return None


def _check_type(text: str, current: Any, value: Any, declared: str | None = None) -> Any:
    if declared == "int" and isinstance(value, float) and not value.is_integer():
        raise OverrideError(f"'{text}': this field is an integer (int), got {value!r}.")
    if value is None or current is None or dataclasses.is_dataclass(current):
        return value
    if isinstance(value, (list, tuple)) and declared and ("tuple" in declared or "list" in declared):
        return value  # e.g. an action term's ``scale: float | tuple[float, ...]``: per-joint values
    if isinstance(current, bool):
        if not isinstance(value, bool):
            raise OverrideError(f"'{text}': expects true or false, got {value!r}.")
    elif isinstance(current, (int, float)):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise OverrideError(f"'{text}': expects a number, got {value!r}.")
        if isinstance(current, int) and isinstance(value, float) and value.is_integer():
            value = int(value)
    return value


def _write(text: str, obj: Any, path: list[str], value: Any) -> None:
    leaf, parent = path[-1], ".".join(path[:-1])
    if isinstance(obj, dict):
        obj[leaf] = _check_type(text, obj.get(leaf), value)
        return
    value = _check_type(text, getattr(obj, leaf), value, _declared_type(obj, leaf))
    try:
        # the configclass update resolves "module:function" strings, lists -> tuples, dicts -> configs
        update_class_from_dict(obj, {leaf: value}, _ns=parent)
    except (KeyError, ValueError, TypeError) as e:
        raise OverrideError(f"'{text}': {e}") from e


def apply_overrides(env_cfg: Any, agent_cfg: Any, overrides: Sequence[str]) -> None:
    """Apply Hydra ``overrides`` to the two configs in place, in order (see the module docstring)."""
    if not overrides:
        return  # without importing OmegaConf (0.03 s of every start-up)
    from omegaconf import OmegaConf
    from omegaconf.errors import OmegaConfBaseException

    parsed = _parse(overrides)
    roots = {"env": env_cfg, "agent": agent_cfg}
    for override in parsed:  # simlab's key check first: its errors name the nearest valid keys
        path = override.key_or_group.split(".")
        _check_root(override.input_line, path)
        _parent(override.input_line, path, roots, override.is_add() or override.is_force_add())
    name = f"simlab_overrides_{next(_store_ids)}"
    _store(name, env_cfg, agent_cfg)
    composed = _compose(name, list(overrides))
    for override in parsed:
        path = override.key_or_group.split(".")
        value = None
        if not override.is_delete():
            try:
                node = OmegaConf.select(composed, override.key_or_group, throw_on_missing=False)
                value = OmegaConf.to_container(node, resolve=True) if OmegaConf.is_config(node) else node
            except OmegaConfBaseException as err:  # an interpolation to a key that does not exist, ...
                raise OverrideError(
                    f"'{override.input_line}': {str(err).splitlines()[0]} "
                    "(an interpolation names an existing key, e.g. ${env.sim.dt})."
                ) from err
            value = replace_strings_with_slices(value)
        obj = _parent(override.input_line, path, roots, override.is_add() or override.is_force_add())
        _write(override.input_line, obj, path, value)


def env_overrides_in(overrides: Sequence[str]) -> list[str]:
    """The overrides that change the env (``env.x=v``, and ``+env.``, ``++env.``, ``~env.`` ones): what a
    trained policy needs again wherever it plays."""
    return [o for o in overrides if o.lstrip("+~").startswith("env.")]


def hydra_task_config(task_name: str, agent_cfg_entry_point: str | None) -> Callable:
    """Decorate ``main(env_cfg, agent_cfg)``: register the task's configs with Hydra, compose the
    overrides in ``sys.argv[1:]`` onto them and call ``main`` with the two config objects.

    Scripts parse their own flags first and leave only the overrides in ``sys.argv``::

        args_cli, hydra_args = parser.parse_known_args()
        sys.argv = [sys.argv[0]] + hydra_args

        @hydra_task_config(args_cli.task, "rsl_rl_cfg_entry_point")
        def main(env_cfg, agent_cfg): ...
    """

    def decorator(func: Callable) -> Callable:
        @functools.wraps(func)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            env_cfg, agent_cfg = register_task_to_hydra(task_name.split(":")[-1], agent_cfg_entry_point)
            # "module:name" values name functions of simlab, the task's package or the script's only
            packages = {"simlab", type(env_cfg).__module__.split(".")[0], func.__module__.split(".")[0]}
            with callable_modules(packages):
                apply_overrides(env_cfg, agent_cfg, sys.argv[1:])
                return func(env_cfg, agent_cfg, *args, **kwargs)

        return wrapper

    return decorator
