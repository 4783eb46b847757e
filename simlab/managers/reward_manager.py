"""Rewards: ``sum(weight * term(env) * step_dt)`` over the terms, with per-term episode sums.

At a reset the episode sums of the resetting envs are logged as ``Episode_Reward/<term>``
(averaged over those envs and divided by the episode length in seconds, as Isaac Lab does).
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Sequence
from typing import TYPE_CHECKING

import torch

from simlab.utils.env_mask import masked_copy_
from simlab.utils.errors import ConfigTypeError

from .manager_base import ManagerBase, ManagerTermBase, format_table
from .manager_term_cfg import RewardTermCfg

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv


class RewardManager(ManagerBase):
    def __init__(self, cfg: object, env: ManagerBasedRLEnv):
        self._terms: list[tuple[str, RewardTermCfg]] = []
        self._class_terms: list[ManagerTermBase] = []
        self._device_weighted: set[int] = set()  # terms whose weight a curriculum sets on the device
        super().__init__(cfg, env)
        n = len(self._terms)
        self._reward_buf = torch.zeros(self.num_envs, device=self.device)
        self._episode_sums = torch.zeros(self.num_envs, n, device=self.device)
        self._step_reward = torch.zeros(self.num_envs, n, device=self.device)
        """(num_envs, num_terms) ``weight * term`` of the last step (per second, before ``dt``)."""
        self._zeros = torch.zeros(self.num_envs, device=self.device)
        self._shared: dict[Hashable, torch.Tensor] | None = None  # a dict while ``compute`` runs

    def __str__(self) -> str:
        rows = [(i, name, float(cfg.weight)) for i, (name, cfg) in enumerate(self._terms)]
        return format_table("Active Reward Terms", ["Index", "Name", "Weight"], rows)

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
    def episode_sums(self) -> dict[str, torch.Tensor]:
        return {name: self._episode_sums[:, i] for i, (name, _) in enumerate(self._terms)}

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> dict[str, torch.Tensor]:
        """Log the episode sums of the resetting envs (mean over them, per second), then zero them."""
        mask = self._mask(env_ids)
        count = mask.sum().clamp(min=1)
        means = (self._episode_sums * mask[:, None]).sum(dim=0) / count / self._env.max_episode_length_s
        extras = {"Episode_Reward/" + name: means[i] for i, (name, _) in enumerate(self._terms)}
        masked_copy_(self._episode_sums, mask, 0.0)
        for term in self._class_terms:
            term.reset(mask)
        return extras

    def compute(self, dt: float) -> torch.Tensor:
        """The (num_envs,) reward of this env step."""
        if not self._terms:
            return self._reward_buf
        self._shared = {}
        try:
            values = [
                self._zeros if cfg.weight == 0.0 else self._column(cfg.func(self._env, **cfg.params))
                for _, cfg in self._terms
            ]
        finally:
            self._shared = None
        # Weights are refreshed from the term configs every step (curricula may change them); the
        # copy goes through a host buffer so a captured step reads the current values on replay.
        torch.mul(torch.stack(values, dim=1), self._current_weights(), out=self._step_reward)
        self._episode_sums.add_(self._step_reward, alpha=dt)
        torch.sum(self._step_reward, dim=1, out=self._reward_buf).mul_(dt)
        return self._reward_buf

    def shared(self, key: Hashable, compute: Callable[[], torch.Tensor]) -> torch.Tensor:
        """``compute()`` once per ``compute`` of the rewards for ``key``: a quantity several terms read
        (whether an env is commanded or moving, the feet's speeds) costs its kernels once a step. The
        state and the commands do not change while the terms run; outside ``compute`` it is computed
        anew. Terms read the tensor and do not write into it. (Python's dict: a captured step records
        one computation.)"""
        if self._shared is None:
            return compute()
        value = self._shared.get(key)
        if value is None:
            value = self._shared[key] = compute()
        return value

    def _column(self, value) -> torch.Tensor:
        """A term's (num_envs,) values; a number (or 0-d tensor) counts for every env."""
        if isinstance(value, torch.Tensor) and value.dim() == 1:
            return value
        return torch.as_tensor(value, dtype=torch.float32, device=self.device).expand(self.num_envs)

    def _current_weights(self) -> torch.Tensor:
        """The term weights as a device tensor, copied again only when a config's weight changed.

        A step replayed as a graph does not run this Python: a curriculum that changes a weight
        calls ``set_term_cfg`` (between steps), which refreshes the tensor the graph reads.
        """
        weights = tuple(float(cfg.weight) for _, cfg in self._terms)
        if getattr(self, "_weights_of", None) != weights:
            if not hasattr(self, "_weights"):
                self._weights = torch.zeros(len(self._terms), device=self.device)
            self._weights.copy_(torch.tensor(weights))
            self._weights_of = weights
        return self._weights

    def get_term_cfg(self, term_name: str) -> RewardTermCfg:
        for i, (name, cfg) in enumerate(self._terms):
            if name == term_name:
                if i in self._device_weighted:  # a weight changed on the device: read it back (a sync)
                    cfg.weight = float(self._weights[i])
                return cfg
        raise KeyError(f"No reward term '{term_name}'; reward terms: {self.active_terms}")

    def set_term_weight_where(self, term_name: str, condition: torch.Tensor, weight: float) -> torch.Tensor:
        """Set the weight of ``term_name`` to ``weight`` where the 0-d bool ``condition`` holds, on the
        device (no host read: a captured step does it on every replay); returns the current weight.
        ``get_term_cfg`` reads the weight back. A term whose weight starts at 0 is never computed."""
        index = self.active_terms.index(term_name) if term_name in self.active_terms else None
        if index is None:
            raise KeyError(f"No reward term '{term_name}'; reward terms: {self.active_terms}")
        weights = self._current_weights()
        self._device_weighted.add(index)
        weights[index] = torch.where(condition, torch.full_like(weights[index], weight), weights[index])
        return weights[index].clone()

    def set_term_cfg(self, term_name: str, cfg: RewardTermCfg) -> None:
        for i, (name, _) in enumerate(self._terms):
            if name == term_name:
                self._terms[i] = (name, cfg)
                self._current_weights()  # a captured step reads the weights tensor, not the configs
                return
        raise KeyError(f"No reward term '{term_name}'; reward terms: {self.active_terms}")

    def get_active_iterable_terms(self, env_idx: int) -> Sequence[tuple[str, Sequence[float]]]:
        return [(name, [float(self._step_reward[env_idx, i])]) for i, (name, _) in enumerate(self._terms)]

    def _prepare_terms(self) -> None:
        self._terms = self._checked_terms(RewardTermCfg, min_argc=1)
        for name, term_cfg in self._terms:
            if not isinstance(term_cfg.weight, (int, float)):
                error = self._term_error(name, f"weight must be a number, got {term_cfg.weight!r}")
                raise ConfigTypeError(str(error)) from None

    def _on_sim_started(self) -> None:
        self._class_terms = self._finish_terms(self._terms)
