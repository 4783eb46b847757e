"""Curricula: functions run at resets that change the task as training goes (reward weights, ranges).

``func(env, env_ids, **params)``; a returned number, tensor or dict is logged as ``Curriculum/<term>``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import torch

from simlab.utils.env_mask import term_env_ids

from .manager_base import ManagerBase, ManagerTermBase, format_table
from .manager_term_cfg import CurriculumTermCfg

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv


class CurriculumManager(ManagerBase):
    def __init__(self, cfg: object, env: ManagerBasedRLEnv):
        self._terms: list[tuple[str, CurriculumTermCfg]] = []
        self._class_terms: list[ManagerTermBase] = []
        self._state: dict[str, Any] = {}
        super().__init__(cfg, env)

    def __str__(self) -> str:
        rows = [(i, name) for i, (name, _) in enumerate(self._terms)]
        return format_table("Active Curriculum Terms", ["Index", "Name"], rows)

    @property
    def active_terms(self) -> list[str]:
        return [name for name, _ in self._terms]

    def get_term_cfg(self, term_name: str) -> CurriculumTermCfg:
        for name, cfg in self._terms:
            if name == term_name:
                return cfg
        raise KeyError(f"No curriculum term '{term_name}'; curriculum terms: {self.active_terms}")

    def get_active_iterable_terms(self, env_idx: int) -> Sequence[tuple[str, Sequence[float]]]:
        out = []
        for name, value in self._state.items():
            if isinstance(value, torch.Tensor):
                value = value.flatten().tolist()
            out.append((name, value if isinstance(value, list) else [value]))
        return out

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> dict[str, Any]:
        extras = {}
        for name, value in self._state.items():
            if isinstance(value, dict):
                for key, item in value.items():
                    extras[f"Curriculum/{name}/{key}"] = item
            else:
                extras[f"Curriculum/{name}"] = value
        for term in self._class_terms:
            term.reset(env_ids)
        return extras

    def compute(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> None:
        mask = self._mask(env_ids)
        for name, cfg in self._terms:
            ids = term_env_ids(cfg.func, mask)  # the mask for terms that take one, else ids
            if ids is None:
                continue  # no env resets: as Isaac Lab, curricula run at resets only
            value = cfg.func(self._env, ids, **cfg.params)
            if value is not None:
                self._state[name] = value

    def graph_blockers(self) -> list[str]:
        return [
            f"curriculum term '{name}' takes env ids; mark it @takes_env_mask to take a bool mask"
            for name, cfg in self._terms
            if not getattr(cfg.func, "takes_env_mask", False)
        ]

    def _prepare_terms(self) -> None:
        self._terms = self._checked_terms(CurriculumTermCfg, min_argc=2)

    def _on_sim_started(self) -> None:
        self._class_terms = self._finish_terms(self._terms)
