"""Terminations: boolean terms; ``time_out`` terms truncate the episode, the others terminate it.

At a reset, ``Episode_Termination/<term>`` counts how many of the resetting envs each term ended.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import torch

from .manager_base import ManagerBase, ManagerTermBase, format_table
from .manager_term_cfg import TerminationTermCfg

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv


class TerminationManager(ManagerBase):
    def __init__(self, cfg: object, env: ManagerBasedRLEnv):
        self._terms: list[tuple[str, TerminationTermCfg]] = []
        self._class_terms: list[ManagerTermBase] = []
        super().__init__(cfg, env)
        n = self.num_envs
        self._term_dones = torch.zeros(n, len(self._terms), dtype=torch.bool, device=self.device)
        # per env, the terms that ended its last episode (kept until another one ends)
        self._last_episode_dones = torch.zeros_like(self._term_dones)
        self._truncated_buf = torch.zeros(n, dtype=torch.bool, device=self.device)
        self._terminated_buf = torch.zeros_like(self._truncated_buf)
        self._dones_buf = torch.zeros_like(self._truncated_buf)
        self._time_out_mask = [cfg.time_out for _, cfg in self._terms]

    def __str__(self) -> str:
        rows = [(i, name, cfg.time_out) for i, (name, cfg) in enumerate(self._terms)]
        return format_table("Active Termination Terms", ["Index", "Name", "Time Out"], rows)

    @property
    def _term_names(self) -> list[str]:  # Isaac Lab's attribute
        return [name for name, _ in self._terms]

    @property
    def _term_cfgs(self) -> list:  # Isaac Lab's attribute
        return [cfg for _, cfg in self._terms]

    @property
    def active_terms(self) -> list[str]:
        return [name for name, _ in self._terms]

    @property
    def dones(self) -> torch.Tensor:
        """(num_envs,) terminated or truncated."""
        return self._truncated_buf | self._terminated_buf

    @property
    def time_outs(self) -> torch.Tensor:
        return self._truncated_buf

    @property
    def terminated(self) -> torch.Tensor:
        return self._terminated_buf

    def get_term(self, name: str) -> torch.Tensor:
        """(num_envs,) the value of term ``name`` at the last ``compute``."""
        return self._term_dones[:, self._index(name)]

    def get_term_cfg(self, term_name: str) -> TerminationTermCfg:
        return self._terms[self._index(term_name)][1]

    def set_term_cfg(self, term_name: str, cfg: TerminationTermCfg) -> None:
        self._terms[self._index(term_name)] = (term_name, cfg)
        self._time_out_mask = [c.time_out for _, c in self._terms]

    def _index(self, name: str) -> int:
        for i, (term_name, _) in enumerate(self._terms):
            if term_name == name:
                return i
        raise KeyError(f"No termination term '{name}'; termination terms: {self.active_terms}")

    def get_active_iterable_terms(self, env_idx: int) -> Sequence[tuple[str, Sequence[float]]]:
        return [(name, [float(self._term_dones[env_idx, i])]) for i, (name, _) in enumerate(self._terms)]

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> dict[str, torch.Tensor]:
        """Log how many of the resetting envs each term ended."""
        mask = self._mask(env_ids)
        counts = (self._term_dones & mask[:, None]).sum(dim=0)
        extras = {"Episode_Termination/" + name: counts[i] for i, (name, _) in enumerate(self._terms)}
        for term in self._class_terms:
            term.reset(mask)
        return extras

    def compute(self) -> torch.Tensor:
        """(num_envs,) bool: which envs are done after this step (the same tensor every call)."""
        self._truncated_buf.zero_()
        self._terminated_buf.zero_()
        for i, (_, cfg) in enumerate(self._terms):
            value = cfg.func(self._env, **cfg.params)
            self._term_dones[:, i] = value
            if self._time_out_mask[i]:
                self._truncated_buf |= value
            else:
                self._terminated_buf |= value
        ended = self._term_dones.any(dim=1, keepdim=True)
        torch.where(ended, self._term_dones, self._last_episode_dones, out=self._last_episode_dones)
        return torch.logical_or(self._truncated_buf, self._terminated_buf, out=self._dones_buf)

    def _prepare_terms(self) -> None:
        self._terms = self._checked_terms(TerminationTermCfg, min_argc=1)

    def _on_sim_started(self) -> None:
        self._class_terms = self._finish_terms(self._terms)
