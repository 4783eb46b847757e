"""Events: functions applied at ``prestartup``/``startup`` (once), on ``reset`` (to the resetting
envs) or at ``interval``s (each env on its own timer, or one global timer). Any other mode name is a
custom mode, applied when code calls ``event_manager.apply(mode=...)`` with it (as in Isaac Lab).

Randomizations (masses, frictions, gains, gravity) are events; they change per-world model fields.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import torch

from simlab.utils.env_mask import masked_copy_, term_env_ids, term_host_read
from simlab.utils.string import closest_matches

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

    # Isaac Lab's internal views, read by code and tests written against its event manager.
    @property
    def _mode_term_cfgs(self) -> dict[str, list[EventTermCfg]]:
        return {mode: [cfg for _, cfg in terms] for mode, terms in self._mode_terms.items()}

    @property
    def _mode_class_term_cfgs(self) -> dict[str, list[EventTermCfg]]:
        """The terms whose ``func`` is a ``ManagerTermBase`` class (or, once built, instance), by mode."""
        by_mode = {}
        for mode, terms in self._mode_terms.items():
            cfgs = [cfg for _, cfg in terms if isinstance(cfg.func, (type, ManagerTermBase))]
            if cfgs:
                by_mode[mode] = cfgs
        return by_mode

    @property
    def _interval_term_time_left(self) -> list[torch.Tensor]:
        return [self._interval_time_left[name] for name, _ in self._mode_terms.get("interval", [])]

    @property
    def _reset_term_last_triggered_step_id(self) -> list[torch.Tensor]:
        return [self._reset_last_step[name] for name, _ in self._mode_terms.get("reset", [])]

    @property
    def _reset_term_last_triggered_once(self) -> list[torch.Tensor]:
        return [self._reset_triggered_once[name] for name, _ in self._mode_terms.get("reset", [])]

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
        mask = self._mask(env_ids)
        for terms in self._class_terms.values():
            for term in terms:
                term.reset(mask)
        # Per-env interval timers restart with the episode (Isaac Lab's behaviour).
        for name, term_cfg in self._mode_terms.get("interval", []):
            if not term_cfg.is_global_time:
                masked_copy_(self._interval_time_left[name], mask, self._draw_interval(term_cfg, self.num_envs))
        return {}

    def apply(
        self,
        mode: str,
        env_ids: Sequence[int] | torch.Tensor | None = None,
        dt: float | None = None,
        global_env_step_count: int | torch.Tensor | None = None,
    ) -> None:
        """Apply the terms of ``mode`` to ``env_ids`` (ids or a bool mask; all envs when None).

        ``interval`` needs ``dt``; ``reset`` with a minimum step count between resets needs
        ``global_env_step_count`` (an int, or a device tensor so that a graphed step reads the
        current count). Envs are selected by mask throughout: terms marked ``takes_env_mask`` get
        the mask, the others get ids (see ``simlab.utils.env_mask.term_env_ids``).
        """
        if not isinstance(mode, str) or not mode:
            raise ValueError(f"An event mode is a non-empty string such as 'reset', got {mode!r}.")
        if mode not in self._mode_terms:
            if mode not in MODES:  # Isaac Lab skips a mode no term declares, with a warning
                print(f"[simlab] EventManager: no event term has mode '{mode}' (modes: {self.available_modes}).")
            return
        if mode == "interval" and dt is None:
            raise ValueError("EventManager.apply(mode='interval') needs the time step dt")
        mask = self._mask(env_ids)
        if isinstance(global_env_step_count, torch.Tensor):  # in the dtype of the per-term steps, once
            global_env_step_count = global_env_step_count.to(torch.int32)
        for name, term_cfg in self._mode_terms[mode]:
            selected = mask
            if mode == "interval":
                time_left = self._interval_time_left[name]
                time_left -= dt
                due = time_left < 1e-6
                masked_copy_(time_left, due, self._draw_interval(term_cfg, len(time_left)))
                selected = due.expand(self.num_envs) if term_cfg.is_global_time else due
            elif mode == "reset" and term_cfg.min_step_count_between_reset > 0:
                if global_env_step_count is None:
                    raise ValueError(
                        f"Event term '{name}' has min_step_count_between_reset > 0: apply(mode='reset') needs"
                        " global_env_step_count"
                    )
                last, once = self._reset_last_step[name], self._reset_triggered_once[name]
                waited = (global_env_step_count - last) >= term_cfg.min_step_count_between_reset
                selected = mask & (waited | ~once)
            if mode == "reset" and global_env_step_count is not None:
                masked_copy_(self._reset_last_step[name], selected, global_env_step_count)
                masked_copy_(self._reset_triggered_once[name], selected, True)
            if mode in ("startup", "prestartup"):
                all_ids = torch.arange(self.num_envs, device=self.device)
                term_cfg.func(self._env, all_ids if env_ids is None else env_ids, **term_cfg.params)
                continue
            ids = term_env_ids(term_cfg.func, selected)
            if ids is not None:
                term_cfg.func(self._env, ids, **term_cfg.params)

    def graph_blockers(self) -> list[str]:
        blockers = []
        for mode in ("reset", "interval"):
            for name, cfg in self._mode_terms.get(mode, []):
                term = f"event term '{name}' (mode '{mode}')"
                if not getattr(cfg.func, "takes_env_mask", False):
                    blockers.append(f"{term} takes env ids; mark it @takes_env_mask to take a bool mask")
                elif reason := term_host_read(cfg.func, self._env, cfg.params):
                    blockers.append(f"{term} {reason}")
        return blockers

    def _draw_interval(self, term_cfg: EventTermCfg, n: int) -> torch.Tensor:
        lower, upper = term_cfg.interval_range_s
        return torch.rand(n, device=self.device) * (upper - lower) + lower

    # -- building --------------------------------------------------------------------------------

    def _prepare_terms(self) -> None:
        for name, term_cfg in self._checked_terms(EventTermCfg, min_argc=2):
            if not isinstance(term_cfg.mode, str) or not term_cfg.mode:
                raise self._term_error(
                    name, f"mode must be {list(MODES)} or a custom mode name (a string), got {term_cfg.mode!r}"
                )
            if term_cfg.mode not in MODES:
                close = closest_matches(term_cfg.mode, MODES, n=1)
                if close:  # a custom mode that looks like a typo of a built-in one
                    print(
                        f"[simlab] EventManager: term '{name}' has the custom mode '{term_cfg.mode}': it runs only"
                        f" when code calls event_manager.apply(mode='{term_cfg.mode}'). Did you mean '{close[0]}'?"
                    )
            if term_cfg.mode == "interval":
                rng = term_cfg.interval_range_s
                if rng is None or len(rng) != 2 or rng[0] > rng[1] or rng[0] < 0:
                    raise self._term_error(name, f"interval events need interval_range_s=(min, max) seconds, got {rng}")
            elif term_cfg.interval_range_s is not None:
                raise self._term_error(
                    name, f"interval_range_s is only for mode 'interval' (mode is '{term_cfg.mode}')"
                )
            self._mode_terms.setdefault(term_cfg.mode, []).append((name, term_cfg))

    def _on_sim_started(self) -> None:
        # Per-env timers only now: the manager is made before sim.reset() (for "prestartup" terms),
        # which first checks that the worlds fit in memory.
        for name, term_cfg in self._mode_terms.get("interval", []):
            n = 1 if term_cfg.is_global_time else self.num_envs
            self._interval_time_left[name] = self._draw_interval(term_cfg, n)
        for name, _ in self._mode_terms.get("reset", []):
            self._reset_last_step[name] = torch.zeros(self.num_envs, dtype=torch.int32, device=self.device)
            self._reset_triggered_once[name] = torch.zeros(self.num_envs, dtype=torch.bool, device=self.device)
        for mode, terms in self._mode_terms.items():
            if mode != "prestartup":
                self._class_terms[mode] = self._finish_terms(terms)
