"""Bases of the managers and of class-based terms.

A manager turns the term configs declared as fields of a config class into callable terms. It
checks each term when it is built, so that a misspelled function, a parameter the function does
not take, a required one missing, or an entity that is not in the scene fails at construction with
a message naming the term, instead of at the first step.
"""

from __future__ import annotations

import copy
import dataclasses
import inspect
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import torch

from simlab.utils.env_mask import env_mask
from simlab.utils.errors import ConfigError
from simlab.utils.string import closest_matches, resolve_matching_names, string_to_callable

from .manager_term_cfg import ManagerTermBaseCfg
from .scene_entity_cfg import SceneEntityCfg

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv


class ManagerTermBase:
    """A term with state: built once with ``(cfg, env)``, then called like a term function.

    Subclasses implement ``__call__(env, **params)`` (events and curricula: ``(env, env_ids,
    **params)``) and may implement ``reset(env_ids)``. Managers pass ``reset`` a ``(num_envs,)``
    bool mask of the envs that reset; ``buffer[env_ids] = 0`` works with it, and
    ``masked_copy_(buffer, env_ids, 0)`` (``simlab.utils.env_mask``) also keeps a CUDA-graphed step.
    """

    def __init__(self, cfg: ManagerTermBaseCfg, env: ManagerBasedEnv):
        self.cfg = cfg
        self._env = env

    @property
    def num_envs(self) -> int:
        return self._env.num_envs

    @property
    def device(self) -> str:
        return self._env.device

    @property
    def __name__(self) -> str:  # so that tables and errors name it like a function
        return type(self).__name__

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> None:
        pass

    def serialize(self) -> dict:
        """What describes the term (Isaac Lab's: its config as a dict)."""
        return {"cfg": self.cfg.to_dict() if hasattr(self.cfg, "to_dict") else self.cfg}

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        raise NotImplementedError(f"{type(self).__name__} must implement __call__")


def cfg_items(cfg: Any) -> list[tuple[str, Any]]:
    """The ``(name, value)`` fields of a config class (or dict) in declaration order, skipping None."""
    if cfg is None:
        return []
    # Instance attributes, not only dataclass fields: terms may be added to a config after creation.
    items = list(cfg.items()) if isinstance(cfg, dict) else list(vars(cfg).items())
    return [(name, value) for name, value in items if value is not None and not name.startswith("_")]


def format_table(title: str, header: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """A plain-text table, like the ones Isaac Lab prints at start-up."""
    if not rows:
        return f"{title}: none"
    cells = [[str(h) for h in header]] + [[_fmt(c) for c in row] for row in rows]
    widths = [max(len(r[i]) for r in cells) for i in range(len(header))]
    inner = sum(widths) + 3 * len(widths) - 1
    if len(title) + 2 > inner:
        widths[-1] += len(title) + 2 - inner
        inner = len(title) + 2
    rule = "+" + "+".join("-" * (w + 2) for w in widths) + "+"
    lines = ["+" + "-" * inner + "+", "|" + title.center(inner) + "|", rule]
    lines.append("| " + " | ".join(c.ljust(w) for c, w in zip(cells[0], widths)) + " |")
    lines.append(rule)
    lines += ["| " + " | ".join(c.ljust(w) for c, w in zip(r, widths)) + " |" for r in cells[1:]]
    lines.append(rule)
    return "\n".join(lines)


def _fmt(value: Any) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def func_name(func: Any) -> str:
    return getattr(func, "__name__", type(func).__name__)


class ManagerBase:
    """Builds, checks and holds the terms of one config class."""

    def __init__(self, cfg: object, env: ManagerBasedEnv):
        self.cfg = copy.deepcopy(cfg)
        self._env = env
        # class terms' required parameters, by id of their params dict: checked once built
        self._class_term_required: dict[int, tuple[list[str], list[str]]] = {}
        self._prepare_terms()
        # Terms that need the scene (entity ids, class terms) are finished once the sim has started.
        env.sim.add_reset_callback(lambda sim: self._on_sim_started())

    @property
    def num_envs(self) -> int:
        return self._env.num_envs

    @property
    def device(self) -> str:
        return self._env.device

    @property
    def active_terms(self) -> list[str] | dict[str, list[str]]:
        raise NotImplementedError

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> dict[str, torch.Tensor]:
        """Reset per-env state of the terms; returns what to log about the finished episodes.

        ``env_ids`` may be ids or a ``(num_envs,)`` bool mask (what an env step passes): managers
        reset by mask, with fixed shapes (see ``simlab.utils.env_mask``).
        """
        return {}

    def graph_blockers(self) -> list[str]:
        """Terms that select envs by ids (so an env step that runs them cannot be a CUDA graph)."""
        return []

    def _mask(self, env_ids: Sequence[int] | torch.Tensor | None) -> torch.Tensor:
        """``env_ids`` as a ``(num_envs,)`` bool mask on the env's device."""
        return env_mask(env_ids, self.num_envs, self.device)

    def find_terms(self, name_keys: str | Sequence[str]) -> list[str]:
        """Names of the active terms matching names or regular expressions."""
        terms = self.active_terms
        names = [n for group in terms.values() for n in group] if isinstance(terms, dict) else terms
        return resolve_matching_names(name_keys, names)[1]

    def get_active_iterable_terms(self, env_idx: int) -> Sequence[tuple[str, Sequence[float]]]:
        raise NotImplementedError

    # -- building --------------------------------------------------------------------------------

    def _prepare_terms(self) -> None:
        raise NotImplementedError

    def _on_sim_started(self) -> None:
        """Resolve scene entities and build class-based terms (called once the sim is reset)."""

    def _checked_terms(self, term_type: type, min_argc: int) -> list[tuple[str, Any]]:
        """The config's ``(name, term_cfg)`` pairs in order, each a ``term_type`` with a valid function."""
        terms = []
        for name, term_cfg in cfg_items(self.cfg):
            if not isinstance(term_cfg, term_type):
                wanted, got = term_type.__name__, type(term_cfg).__name__
                article = "an" if wanted[0] in "AEIOU" else "a"
                raise TypeError(f"{type(self).__name__}: term '{name}' must be {article} {wanted}, got {got}")
            self._resolve_common_term_cfg(name, term_cfg, min_argc=min_argc)
            terms.append((name, term_cfg))
        return terms

    def _finish_terms(self, terms: list[tuple[str, Any]], prefix: str = "") -> list[ManagerTermBase]:
        """Resolve the terms' scene entities and build their classes (once the sim has started);
        returns the class-based term instances, which ``reset`` must reach."""
        class_terms = []
        for name, term_cfg in terms:
            self._resolve_scene_entities(prefix + name, term_cfg)
            self._build_class_term(prefix + name, term_cfg)
            if isinstance(term_cfg.func, ManagerTermBase):
                class_terms.append(term_cfg.func)
        return class_terms

    def _term_error(self, name: str, message: str) -> ConfigError:
        return ConfigError(f"{type(self).__name__}: term '{name}': {message}")

    def _resolve_common_term_cfg(self, name: str, term_cfg: ManagerTermBaseCfg, min_argc: int = 1) -> None:
        """Check a term's function and parameters against its signature (no scene needed)."""
        if not isinstance(term_cfg, ManagerTermBaseCfg):
            raise TypeError(
                f"{type(self).__name__}: term '{name}' must be a {ManagerTermBaseCfg.__name__} subclass"
                f" config, got {type(term_cfg).__name__}"
            )
        if term_cfg.func is dataclasses.MISSING:
            raise self._term_error(name, "no 'func' given")
        if isinstance(term_cfg.func, str):
            try:
                term_cfg.func = string_to_callable(term_cfg.func)
            except (ValueError, TypeError) as err:
                raise self._term_error(name, str(err)) from err
        if not callable(term_cfg.func):
            raise self._term_error(name, f"'func' must be a function or a ManagerTermBase class, got {term_cfg.func!r}")
        if not isinstance(term_cfg.params, dict):
            raise self._term_error(name, f"'params' must be a dict, got {type(term_cfg.params).__name__}")
        self._check_params(name, term_cfg.func, term_cfg.params, min_argc)

    def _check_params(self, name: str, func: Any, params: dict, min_argc: int) -> None:
        if inspect.isclass(func):
            if not issubclass(func, ManagerTermBase):
                raise self._term_error(name, f"class {func.__name__} must subclass ManagerTermBase")
            target, skip = func.__call__, 1 + min_argc  # self, then env (, env_ids)
        else:
            target, skip = func, min_argc
        try:
            parameters = list(inspect.signature(target).parameters.values())
        except (TypeError, ValueError):
            return  # builtins without a signature: nothing to check
        kinds = inspect.Parameter
        if any(p.kind == kinds.VAR_POSITIONAL for p in parameters):
            return
        if len(parameters) < skip:
            first = "(env, env_ids, ...)" if min_argc == 2 else "(env, ...)"
            raise self._term_error(name, f"{func_name(func)} must take {first} as its first argument(s)")
        rest = [p for p in parameters[skip:] if p.kind in (kinds.POSITIONAL_OR_KEYWORD, kinds.KEYWORD_ONLY)]
        accepted = [p.name for p in rest]
        required = [p.name for p in rest if p.default is kinds.empty]
        takes_any = any(p.kind == kinds.VAR_KEYWORD for p in parameters)
        unknown = [k for k in params if k not in accepted] if not takes_any else []
        if unknown:
            hints = "".join(
                f" ('{k}': did you mean '{c[0]}'?)" for k in unknown if (c := closest_matches(k, accepted, 1))
            )
            raise self._term_error(
                name, f"{func_name(func)} got unknown parameter(s) {unknown}.{hints} It takes {accepted}"
            )
        if inspect.isclass(func):
            # A class term's __init__ may fill in parameters (as Isaac Lab's power_consumption adds its
            # asset_cfg): the required ones are checked once it is built (_build_class_term).
            self._class_term_required[id(params)] = (required, accepted)
            return
        self._check_required(name, func, params, required, accepted)

    def _check_required(self, name: str, func: Any, params: dict, required: list[str], accepted: list[str]) -> None:
        missing = [k for k in required if k not in params]
        if missing:
            raise self._term_error(
                name, f"{func_name(func)} needs parameter(s) {missing} in 'params' (it takes {accepted})"
            )

    def _resolve_scene_entities(self, name: str, term_cfg: ManagerTermBaseCfg) -> None:
        for key, value in term_cfg.params.items():
            if isinstance(value, SceneEntityCfg):
                try:
                    value.resolve(self._env.scene)
                except (ValueError, KeyError) as err:
                    raise self._term_error(name, f"parameter '{key}': {err}") from err

    def _build_class_term(self, name: str, term_cfg: ManagerTermBaseCfg) -> None:
        if inspect.isclass(term_cfg.func):
            cls, given = term_cfg.func, set(term_cfg.params)
            try:
                term_cfg.func = cls(cfg=term_cfg, env=self._env)
            except (ValueError, KeyError) as err:
                raise self._term_error(name, str(err)) from err
            required, accepted = self._class_term_required.pop(id(term_cfg.params), ([], []))
            self._check_required(name, cls, term_cfg.params, required, accepted)
            if set(term_cfg.params) != given:  # entities the class added get resolved like the config's
                self._resolve_scene_entities(name, term_cfg)
