"""Events: functions applied at ``prestartup``/``startup`` (once), on ``reset`` (to the resetting
envs) or at ``interval``s (each env on its own timer, or one global timer).

Randomizations (masses, frictions, gains, gravity) are events; they change per-world model fields.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import torch

from .manager_base import ManagerBase, ManagerTermBase, format_table
from .manager_term_cfg import EventTermCfg

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv

MODES = ("prestartup", "startup", "reset", "interval")


class EventManager(ManagerBase):
    def __init__(self, cfg: object, env: ManagerBasedEnv):
        self._mode_terms: dict[str, list[tuple[str, EventTermCfg]]] = {}
        self._interval_time_left: dict[str, torch.Tensor] = {}
        self._reset_last_step: dict[str, torch.Tensor] = {}
        self._reset_triggered_once: dict[str, torch.Tensor] = {}
        self._class_terms: dict[str, list[ManagerTermBase]] = {}
        super().__init__(cfg, env)

    def __str__(self) -> str:
        tables = []
        for mode, terms in self._mode_terms.items():
            if mode == "interval":
                rows = [(i, name, term.interval_range_s) for i, (name, term) in enumerate(terms)]
                tables.append(
                    format_table(
                        f"Active Event Terms in Mode: '{mode}'", ["Index", "Name", "Interval time range (s)"], rows
                    )
                )
            else:
                rows = [(i, name) for i, (name, _) in enumerate(terms)]
                tables.append(format_table(f"Active Event Terms in Mode: '{mode}'", ["Index", "Name"], rows))
        return "\n".join(tables) if tables else "<EventManager> no event terms"

    @property
    def active_terms(self) -> dict[str, list[str]]:
        return {mode: [name for name, _ in terms] for mode, terms in self._mode_terms.items()}

    @property
    def available_modes(self) -> list[str]:
        return list(self._mode_terms)

    def get_term_cfg(self, term_name: str) -> EventTermCfg:
        for terms in self._mode_terms.values():
            for name, cfg in terms:
                if name == term_name:
                    return cfg
        raise KeyError(f"No event term '{term_name}'; event terms: {self.active_terms}")

    def set_term_cfg(self, term_name: str, cfg: EventTermCfg) -> None:
        for terms in self._mode_terms.values():
            for i, (name, _) in enumerate(terms):
                if name == term_name:
                    terms[i] = (name, cfg)
                    return
        raise KeyError(f"No event term '{term_name}'; event terms: {self.active_terms}")

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> dict[str, torch.Tensor]:
        for terms in self._class_terms.values():
            for term in terms:
                term.reset(env_ids)
        # Per-env interval timers restart with the episode (Isaac Lab's behaviour).
        for name, term_cfg in self._mode_terms.get("interval", []):
            if not term_cfg.is_global_time:
                env = slice(None) if env_ids is None else env_ids
                time_left = self._interval_time_left[name]
                lower, upper = term_cfg.interval_range_s
                time_left[env] = torch.rand_like(time_left[env]) * (upper - lower) + lower
        return {}

    def apply(
        self,
        mode: str,
        env_ids: Sequence[int] | torch.Tensor | None = None,
        dt: float | None = None,
        global_env_step_count: int | None = None,
    ) -> None:
        """Apply the terms of ``mode``; ``interval`` needs ``dt``, ``reset`` with a minimum step count
        between resets needs ``global_env_step_count``."""
        if mode not in MODES:
            raise ValueError(f"Unknown event mode '{mode}'; modes: {list(MODES)}")
        if mode not in self._mode_terms:
            return
        if mode == "interval" and dt is None:
            raise ValueError("EventManager.apply(mode='interval') needs the time step dt")
        all_ids = torch.arange(self.num_envs, device=self.device)
        if env_ids is None:
            env_ids = all_ids
        elif not isinstance(env_ids, torch.Tensor):
            env_ids = torch.as_tensor(list(env_ids), dtype=torch.long, device=self.device)
        for name, term_cfg in self._mode_terms[mode]:
            if mode == "interval":
                time_left = self._interval_time_left[name]
                time_left -= dt
                lower, upper = term_cfg.interval_range_s
                if term_cfg.is_global_time:
                    if float(time_left[0]) < 1e-6:
                        time_left[:] = torch.rand(1, device=self.device) * (upper - lower) + lower
                        term_cfg.func(self._env, all_ids, **term_cfg.params)
                    continue
                due = time_left < 1e-6
                ids = due.nonzero().flatten()
                if len(ids):
                    time_left[ids] = torch.rand(len(ids), device=self.device) * (upper - lower) + lower
                    term_cfg.func(self._env, ids, **term_cfg.params)
            elif mode == "reset" and term_cfg.min_step_count_between_reset > 0:
                if global_env_step_count is None:
                    raise ValueError(
                        f"Event term '{name}' has min_step_count_between_reset > 0: apply(mode='reset') needs"
                        " global_env_step_count"
                    )
                last, once = self._reset_last_step[name], self._reset_triggered_once[name]
                steps_since = global_env_step_count - last[env_ids]
                valid = (steps_since >= term_cfg.min_step_count_between_reset) | ~once[env_ids]
                ids = env_ids[valid]
                if len(ids):
                    last[ids] = global_env_step_count
                    once[ids] = True
                    term_cfg.func(self._env, ids, **term_cfg.params)
            else:
                if mode == "reset" and global_env_step_count is not None:
                    self._reset_last_step[name][env_ids] = global_env_step_count
                    self._reset_triggered_once[name][env_ids] = True
                term_cfg.func(self._env, env_ids, **term_cfg.params)

    # -- building --------------------------------------------------------------------------------

    def _prepare_terms(self) -> None:
        for name, term_cfg in self._checked_terms(EventTermCfg, min_argc=2):
            if term_cfg.mode not in MODES:
                raise self._term_error(name, f"unknown mode '{term_cfg.mode}'; modes: {list(MODES)}")
            if term_cfg.mode == "interval":
                rng = term_cfg.interval_range_s
                if rng is None or len(rng) != 2 or rng[0] > rng[1] or rng[0] < 0:
                    raise self._term_error(name, f"interval events need interval_range_s=(min, max) seconds, got {rng}")
                n = 1 if term_cfg.is_global_time else self.num_envs
                lower, upper = rng
                self._interval_time_left[name] = torch.rand(n, device=self.device) * (upper - lower) + lower
            elif term_cfg.interval_range_s is not None:
                raise self._term_error(
                    name, f"interval_range_s is only for mode 'interval' (mode is '{term_cfg.mode}')"
                )
            if term_cfg.mode == "reset":
                self._reset_last_step[name] = torch.zeros(self.num_envs, dtype=torch.long, device=self.device)
                self._reset_triggered_once[name] = torch.zeros(self.num_envs, dtype=torch.bool, device=self.device)
            self._mode_terms.setdefault(term_cfg.mode, []).append((name, term_cfg))

    def _on_sim_started(self) -> None:
        for mode, terms in self._mode_terms.items():
            if mode != "prestartup":
                self._class_terms[mode] = self._finish_terms(terms)
