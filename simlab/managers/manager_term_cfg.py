"""Configuration of manager terms: what an observation, reward, termination, event, command,
curriculum or action term computes, and with which parameters.

A term is a function ``func(env, **params)`` (events and curricula: ``func(env, env_ids, **params)``)
or a ``ManagerTermBase`` subclass, instantiated once with ``(cfg, env)`` and then called like the
function. Parameters that are ``SceneEntityCfg`` are resolved against the scene (names to ids) once
the simulation starts.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import MISSING
from typing import Any

from simlab.utils import configclass
from simlab.utils.modifiers import ModifierCfg
from simlab.utils.noise import NoiseCfg


@configclass
class ManagerTermBaseCfg:
    func: Callable | type = MISSING
    """The term's function, or a ``ManagerTermBase`` subclass (or a ``"module:name"`` string)."""
    params: dict[str, Any] = dict()
    """Keyword arguments passed to ``func`` after the environment (and ``env_ids`` for events)."""


# -- actions ---------------------------------------------------------------------------------------


@configclass
class ActionTermCfg:
    class_type: type = MISSING
    """The ``ActionTerm`` subclass this config builds."""
    asset_name: str = MISSING
    """Name of the scene entity the action drives."""
    debug_vis: bool = False
    clip: dict[str, tuple[float, float]] | None = None
    """Joint-name patterns to ``(min, max)`` bounds of the processed action; None: no clipping."""


# -- recorders --------------------------------------------------------------------------------------


@configclass
class RecorderTermCfg:
    class_type: type = MISSING
    """The ``RecorderTerm`` subclass this config builds."""


# -- commands ----------------------------------------------------------------------------------------


@configclass
class CommandTermCfg:
    class_type: type = MISSING
    resampling_time_range: tuple[float, float] = MISSING
    """Seconds a command is held before it is resampled, drawn uniformly per env."""
    debug_vis: bool = False


# -- curricula ------------------------------------------------------------------------------------


@configclass
class CurriculumTermCfg(ManagerTermBaseCfg):
    """``func(env, env_ids, **params)``, called at env resets; what it returns is logged."""


# -- observations ----------------------------------------------------------------------------------


@configclass
class ObservationTermCfg(ManagerTermBaseCfg):
    """``func(env, **params) -> (num_envs, ...)``, then modifiers, noise, clip, scale, history."""

    modifiers: list[ModifierCfg] | None = None
    noise: NoiseCfg | None = None
    """Added only when the group's ``enable_corruption`` is True."""
    clip: tuple[float, float] | None = None
    scale: tuple[float, ...] | float | None = None
    history_length: int = 0
    """Past values to stack (oldest first); 0 keeps only the current one."""
    flatten_history_dim: bool = True


@configclass
class ObservationGroupCfg:
    """A group of observation terms: declare the terms as fields of a subclass."""

    concatenate_terms: bool = True
    """Concatenate the terms into one tensor (else a dict of terms)."""
    concatenate_dim: int = -1
    enable_corruption: bool = False
    """Apply the terms' noise."""
    history_length: int | None = None
    """If set, overrides every term's ``history_length``."""
    flatten_history_dim: bool = True


# -- events ----------------------------------------------------------------------------------------


@configclass
class EventTermCfg(ManagerTermBaseCfg):
    """``func(env, env_ids, **params)`` run at ``startup``, on ``reset`` or at ``interval``s."""

    mode: str = MISSING
    """``"prestartup"`` (before the model compiles), ``"startup"``, ``"reset"``, ``"interval"``, or a
    custom mode name: applied when code calls ``env.event_manager.apply(mode=name)``."""
    interval_range_s: tuple[float, float] | None = None
    """For ``interval`` events: seconds between two applications, drawn uniformly."""
    is_global_time: bool = False
    """For ``interval`` events: one timer for all envs (True) or one per env (False)."""
    min_step_count_between_reset: int = 0
    """For ``reset`` events: env steps that must pass before the event applies again to an env."""


# -- rewards and terminations ----------------------------------------------------------------------


@configclass
class RewardTermCfg(ManagerTermBaseCfg):
    """``func(env, **params) -> (num_envs,)``; the reward adds ``weight * value * step_dt``."""

    weight: float = MISSING


@configclass
class TerminationTermCfg(ManagerTermBaseCfg):
    """``func(env, **params) -> (num_envs,)`` bool; ``time_out`` terms truncate instead of terminate."""

    time_out: bool = False


# Isaac Lab's short aliases, as task configs import them.
ObsTerm = ObservationTermCfg
ObsGroup = ObservationGroupCfg
EventTerm = EventTermCfg
RewTerm = RewardTermCfg
DoneTerm = TerminationTermCfg
CurrTerm = CurriculumTermCfg

__all__ = [
    "ActionTermCfg",
    "CommandTermCfg",
    "CurriculumTermCfg",
    "EventTermCfg",
    "ManagerTermBaseCfg",
    "ObservationGroupCfg",
    "ObservationTermCfg",
    "RewardTermCfg",
    "TerminationTermCfg",
]
