"""Isaac Lab 3.0's presets inside task configs (``isaaclab_tasks.utils.PresetCfg``, ``preset``) and the
command-line words that choose them.

A task config may hold ``PresetCfg`` slots (:mod:`simlab.utils.presets`): its physics
(``SimulationCfg(physics=MyPhysicsCfg())``), a camera, a scalar (``preset(default=0.0,
newton_mjwarp=0.01)``). :func:`select_presets` resolves the env and agent configs of a run:

* ``presets=a,b``: at every preset that has ``a`` (or ``b``) that alternative, else its ``default``; a
  name that neither the configs nor the task's registered presets have is refused, naming both;
* ``physics=NAME`` (a MuJoCo name: ``mujoco``, ``newton_mjwarp``, ...): the alternative of that name,
  else ``newton_mjwarp``, Isaac Lab 3.0's preset name for MuJoCo Warp, whose solver settings are
  MuJoCo's on either engine; the engine itself is set by :mod:`simlab.cli.isaaclab3`;
* ``env.<path>=NAME`` / ``agent.<path>=NAME`` where ``<path>`` is a preset: that alternative there.

An alternative that asks for a physics backend other than MuJoCo, chosen by name, is refused in one
line; as a task's ``default`` it is held and not used (:mod:`simlab.sim.physics`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from simlab.sim.backend_names import PHYSICS_ADVICE
from simlab.sim.physics import foreign_physics
from simlab.utils.errors import ConfigError
from simlab.utils.presets import PresetCfg, collect_presets, preset, resolve_presets

__all__ = ["MUJOCO_PRESET", "PresetCfg", "preset", "select_presets"]

MUJOCO_PRESET = "newton_mjwarp"
"""Isaac Lab 3.0's preset name for MuJoCo Warp: what ``physics=mujoco`` / ``newton_mjwarp`` choose."""


def _refuse_foreign(path: str, name: str, value: Any) -> None:
    backend = foreign_physics(value)
    if backend is not None:
        raise ConfigError(f"The preset {name} chooses {backend} at {path}: {PHYSICS_ADVICE}.")


def _path_selectors(cfg: Any, root: str, overrides: list[str]) -> tuple[dict[str, str], list[str]]:
    """The overrides ``<root>.<path>=NAME`` whose path is a preset of ``cfg``, and the others."""
    if cfg is None:
        return {}, overrides
    paths = collect_presets(cfg)
    chosen, rest = {}, []
    for word in overrides:
        key, _, value = word.partition("=")
        head, _, path = key.partition(".")
        if head == root and path in paths:
            chosen[path] = value
        else:
            rest.append(word)
    return chosen, rest


def select_presets(
    env_cfg: Any,
    agent_cfg: Any,
    names: Sequence[str] = (),
    physics: str | None = None,
    overrides: Sequence[str] = (),
    registered: Sequence[str] = (),
    task: str = "this task",
) -> tuple[Any, Any, list[str]]:
    """``(env_cfg, agent_cfg, overrides left)`` with every preset of both configs resolved (see the module).

    ``names`` are the ``presets=`` names that are not the task's registered presets (``registered``,
    listed in the refusal of an unknown name); ``physics`` the name given to ``physics=``, if any.
    """
    groups = [[name] for name in names]
    if physics is not None:
        groups.append(list(dict.fromkeys([physics, MUJOCO_PRESET])))
    env_paths, rest = _path_selectors(env_cfg, "env", list(overrides))
    agent_paths, rest = _path_selectors(agent_cfg, "agent", rest)
    available = sorted(
        {n for c in (env_cfg, agent_cfg) if c is not None for a in collect_presets(c).values() for n in a}
    )
    env_cfg, used = resolve_presets(env_cfg, groups, env_paths, _refuse_foreign)
    if agent_cfg is not None:
        agent_cfg, used_agent = resolve_presets(agent_cfg, groups, agent_paths, _refuse_foreign)
        used |= used_agent
    unknown = [name for name in names if name not in used]
    if unknown:
        have = sorted(set(available) - {"default"} | set(registered))
        listed = f"its presets are {', '.join(have)}" if have else "it registers no presets"
        raise ConfigError(f"presets={','.join(unknown)}: not a preset of {task} ({listed}).")
    return env_cfg, agent_cfg, rest
