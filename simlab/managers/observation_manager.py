"""Observations: groups of terms (``"policy"``, ``"critic"``, ...), each a tensor or a dict of terms.

Per term, in order: ``func(env, **params)``, modifiers, noise (if the group enables corruption),
clip, scale, then history (a buffer of the last ``history_length`` values, oldest first, filled
with the first value after a reset).
"""

from __future__ import annotations

import dataclasses
import inspect
from collections.abc import Sequence
from typing import TYPE_CHECKING

import torch

from simlab.utils.env_mask import masked_copy_
from simlab.utils.modifiers import ModifierBase
from simlab.utils.noise import noise_model

from .manager_base import ManagerBase, ManagerTermBase, cfg_items, format_table, func_name
from .manager_term_cfg import ObservationGroupCfg, ObservationTermCfg

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv

_GROUP_FIELDS = {f.name for f in dataclasses.fields(ObservationGroupCfg)}


class _History:
    """The last ``length`` values of a term per env, oldest first (a fresh env's buffer is filled
    with its first value). ``current_length`` counts the values appended since the env's reset, as
    Isaac Lab's ``CircularBuffer`` does."""

    def __init__(self, length: int, num_envs: int, device: str):
        self.length = length
        self.buffer: torch.Tensor | None = None
        self.fresh = torch.ones(num_envs, dtype=torch.bool, device=device)
        self.current_length = torch.zeros(num_envs, dtype=torch.long, device=device)

    @property
    def max_length(self) -> int:
        return self.length

    def with_value(self, value: torch.Tensor) -> torch.Tensor:
        """The buffer after appending ``value`` (not stored)."""
        fill = value.unsqueeze(1).expand(-1, self.length, *value.shape[1:])
        if self.buffer is None:
            return fill.clone()
        shifted = torch.cat([self.buffer[:, 1:], value.unsqueeze(1)], dim=1)
        mask = self.fresh.view(-1, *([1] * (shifted.ndim - 1)))
        return torch.where(mask, fill, shifted)

    def append(self, value: torch.Tensor) -> torch.Tensor:
        self.buffer = self.with_value(value)
        self.current_length.add_(1).clamp_(max=self.length)
        self.fresh[:] = False
        return self.buffer

    def reset(self, mask: torch.Tensor) -> None:
        self.fresh |= mask  # refilled with the next observation
        masked_copy_(self.current_length, mask, 0)


class ObservationManager(ManagerBase):
    def __init__(self, cfg: object, env: ManagerBasedEnv):
        if cfg is None:
            raise ValueError("The observations config is None: declare at least a 'policy' group")
        self._group_terms: dict[str, list[tuple[str, ObservationTermCfg]]] = {}
        self._group_cfgs: dict[str, ObservationGroupCfg] = {}
        self._histories: dict[str, dict[str, _History]] = {}
        self._class_modifiers: list[ModifierBase] = []
        self._class_terms: list[ManagerTermBase] = []
        self._group_obs_term_dim: dict[str, list[tuple[int, ...]]] = {}
        self._group_obs_dim: dict[str, tuple[int, ...] | list[tuple[int, ...]]] = {}
        self._columns: dict[str, tuple[tuple, _ColumnOps | None]] = {}
        super().__init__(cfg, env)

    def __str__(self) -> str:
        tables = []
        for group, terms in self._group_terms.items():
            dims = self._group_obs_term_dim.get(group, [()] * len(terms))
            rows = [(i, name, dims[i]) for i, (name, _) in enumerate(terms)]
            title = f"Active Observation Terms in Group: '{group}'"
            if self._group_cfgs[group].concatenate_terms:
                title += f" (shape: {self._group_obs_dim.get(group)})"
            tables.append(format_table(title, ["Index", "Name", "Shape"], rows))
        return "\n".join(tables)

    # Isaac Lab's attributes, which its tests and some task code read
    @property
    def _group_obs_term_names(self) -> dict[str, list[str]]:
        return {group: [name for name, _ in terms] for group, terms in self._group_terms.items()}

    @property
    def _group_obs_term_cfgs(self) -> dict[str, list[ObservationTermCfg]]:
        return {group: [cfg for _, cfg in terms] for group, terms in self._group_terms.items()}

    @property
    def _group_obs_term_history_buffer(self) -> dict[str, dict[str, _History]]:
        return self._histories

    @property
    def active_terms(self) -> dict[str, list[str]]:
        return {group: [name for name, _ in terms] for group, terms in self._group_terms.items()}

    @property
    def group_obs_dim(self) -> dict[str, tuple[int, ...] | list[tuple[int, ...]]]:
        """Per group: the concatenated shape (without the env dim), or the list of term shapes."""
        return self._group_obs_dim

    @property
    def group_obs_term_dim(self) -> dict[str, list[tuple[int, ...]]]:
        return self._group_obs_term_dim

    @property
    def group_obs_concatenate(self) -> dict[str, bool]:
        return {group: cfg.concatenate_terms for group, cfg in self._group_cfgs.items()}

    def serialize(self) -> dict[str, dict[str, dict]]:
        """Per group and term: a class term's ``serialize()``, else ``{"cfg": <the term's config as a dict>}``."""
        return {
            group: {
                name: cfg.func.serialize() if isinstance(cfg.func, ManagerTermBase) else {"cfg": cfg.to_dict()}
                for name, cfg in terms
            }
            for group, terms in self._group_terms.items()
        }

    def get_term_cfg(self, group: str, name: str) -> ObservationTermCfg:
        for term_name, term_cfg in self._group_terms[group]:
            if term_name == name:
                return term_cfg
        raise KeyError(f"No observation term '{name}' in group '{group}'; terms: {self.active_terms[group]}")

    def get_active_iterable_terms(self, env_idx: int) -> Sequence[tuple[str, Sequence[float]]]:
        out = []
        for group in self._group_terms:
            obs = self.compute_group(group, update_history=False)
            if not isinstance(obs, dict):
                obs = self._terms_as_dict(group, obs)
            out += [(f"{group}-{name}", value[env_idx].flatten().cpu().tolist()) for name, value in obs.items()]
        return out

    def _terms_as_dict(self, group: str, obs: torch.Tensor) -> dict[str, torch.Tensor]:
        out, idx = {}, 0
        for (name, _), dim in zip(self._group_terms[group], self._group_obs_term_dim[group]):
            size = int(torch.tensor(dim).prod())
            out[name] = obs[:, idx : idx + size]
            idx += size
        return out

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> dict[str, torch.Tensor]:
        mask = self._mask(env_ids)
        for term in self._class_terms:
            term.reset(mask)
        for modifier in self._class_modifiers:
            modifier.reset(mask)
        for histories in self._histories.values():
            for history in histories.values():
                history.reset(mask)
        return {}

    def compute(self, update_history: bool = False) -> dict[str, torch.Tensor | dict[str, torch.Tensor]]:
        """Every group's observation. ``update_history=False`` leaves history buffers and stateful
        modifiers as they are (the env step computes the pre-reset observation that way)."""
        return {group: self.compute_group(group, update_history) for group in self._group_terms}

    def compute_group(self, group_name: str, update_history: bool = False) -> torch.Tensor | dict[str, torch.Tensor]:
        if group_name not in self._group_terms:
            raise ValueError(f"No observation group '{group_name}'; groups: {list(self._group_terms)}")
        env = self._env
        columns = self._column_ops(group_name)
        if columns is not None:  # the whole group's noise, clip and scale in a few ops
            terms = self._group_terms[group_name]
            return columns.apply(torch.cat([cfg.func(env, **cfg.params) for _, cfg in terms], dim=-1))
        group_cfg = self._group_cfgs[group_name]
        histories = self._histories[group_name]
        obs: dict[str, torch.Tensor] = {}
        for name, term_cfg in self._group_terms[group_name]:
            value = term_cfg.func(env, **term_cfg.params).clone()
            if term_cfg.modifiers is not None:
                for modifier in term_cfg.modifiers:
                    if isinstance(modifier.func, ModifierBase):
                        value = modifier.func(value) if update_history else modifier.func.peek(value)
                    else:
                        value = modifier.func(value, **modifier.params)
            if term_cfg.noise is not None:
                value = term_cfg.noise.func(value, term_cfg.noise)
            if term_cfg.clip is not None:
                value = value.clip_(min=term_cfg.clip[0], max=term_cfg.clip[1])
            if term_cfg.scale is not None:
                value = value.mul_(term_cfg.scale)
            if name in histories:
                history = histories[name]
                value = history.append(value) if update_history else history.with_value(value)
                if term_cfg.flatten_history_dim:
                    value = value.reshape(value.shape[0], -1)
            obs[name] = value
        if group_cfg.concatenate_terms:
            dim = group_cfg.concatenate_dim
            return torch.cat(list(obs.values()), dim=dim + 1 if dim >= 0 else dim)
        return obs

    def _column_ops(self, group_name: str) -> _ColumnOps | None:
        """The group's per-term noise, clip and scale as per-column ops on the concatenated
        observation, where that gives the same result: a concatenated group of (num_envs, k) terms
        without modifiers or history, whose noises add one kind of sample (uniform, Gaussian or
        constant). Otherwise None (each term is processed on its own). Rebuilt when a term's
        noise, clip or scale changes."""
        dims = self._group_obs_term_dim.get(group_name)
        if dims is None or not self._group_cfgs[group_name].concatenate_terms:
            return None
        terms = self._group_terms[group_name]
        key = tuple(_column_key(cfg) for _, cfg in terms)
        cached = self._columns.get(group_name)
        if cached is not None and cached[0] == key:
            return cached[1]
        fusable = (
            len({kind for kind, *_ in key} - {"none", "constant"}) <= 1  # one kind of random sample
            and all(kind != "other" for kind, *_ in key)
            and all(len(dim) == 1 for dim in dims)
            and not self._histories[group_name]
            and not any(cfg.modifiers for _, cfg in terms)
        )
        widths = [dim[0] for dim in dims]
        ops = _ColumnOps([cfg for _, cfg in terms], widths, self.num_envs, self.device) if fusable else None
        self._columns[group_name] = (key, ops)
        return ops

    # -- building --------------------------------------------------------------------------------

    def _prepare_terms(self) -> None:
        for group_name, group_cfg in cfg_items(self.cfg):
            if not isinstance(group_cfg, ObservationGroupCfg):
                raise TypeError(
                    f"ObservationManager: '{group_name}' must be an ObservationGroupCfg (a group of terms),"
                    f" got {type(group_cfg).__name__}"
                )
            terms = []
            for name, term_cfg in cfg_items(group_cfg):
                if name in _GROUP_FIELDS:
                    continue
                if not isinstance(term_cfg, ObservationTermCfg):
                    raise TypeError(
                        f"ObservationManager: term '{name}' in group '{group_name}' must be an ObservationTermCfg,"
                        f" got {type(term_cfg).__name__}"
                    )
                self._resolve_common_term_cfg(f"{group_name}/{name}", term_cfg, min_argc=1)
                for modifier in term_cfg.modifiers or []:  # functions of (data, **params); classes come later
                    if inspect.isclass(modifier.func):
                        continue
                    if not callable(modifier.func):
                        raise self._term_error(f"{group_name}/{name}", f"modifier {modifier.func!r} is not callable")
                    self._check_params(f"{group_name}/{name} modifier", modifier.func, modifier.params, 1)
                if group_cfg.history_length is not None:
                    term_cfg.history_length = group_cfg.history_length
                    term_cfg.flatten_history_dim = group_cfg.flatten_history_dim
                if not group_cfg.enable_corruption:
                    term_cfg.noise = None
                if term_cfg.scale is not None and not isinstance(term_cfg.scale, (int, float)):
                    term_cfg.scale = torch.tensor(term_cfg.scale, dtype=torch.float32, device=self.device)
                terms.append((name, term_cfg))
            if not terms and group_cfg.concatenate_terms:  # a group kept as a dict may be empty, as in Isaac Lab
                raise ValueError(
                    f"ObservationManager: group '{group_name}' has no terms to concatenate: add a term,"
                    " or set concatenate_terms=False for an empty group"
                )
            self._group_terms[group_name] = terms
            self._group_cfgs[group_name] = group_cfg

    def _on_sim_started(self) -> None:
        env = self._env
        for group_name, terms in self._group_terms.items():
            self._histories[group_name] = {}
            dims = []
            self._class_terms += self._finish_terms(terms, prefix=f"{group_name}/")
            for name, term_cfg in terms:
                try:
                    value = term_cfg.func(env, **term_cfg.params)
                except Exception as err:
                    raise self._term_error(
                        f"{group_name}/{name}", f"{func_name(term_cfg.func)} failed: {err!r}"
                    ) from err
                if not isinstance(value, torch.Tensor) or value.ndim < 1 or value.shape[0] != self.num_envs:
                    shape = tuple(value.shape) if isinstance(value, torch.Tensor) else type(value).__name__
                    raise self._term_error(
                        f"{group_name}/{name}",
                        f"{func_name(term_cfg.func)} must return a (num_envs, ...) tensor, got {shape}",
                    )
                term_dim = tuple(value.shape[1:])
                for modifier in term_cfg.modifiers or []:
                    if inspect.isclass(modifier.func):
                        if not issubclass(modifier.func, ModifierBase):
                            raise self._term_error(
                                f"{group_name}/{name}", f"modifier {modifier.func} must subclass ModifierBase"
                            )
                        modifier.func = modifier.func(cfg=modifier, data_dim=tuple(value.shape), device=self.device)
                        self._class_modifiers.append(modifier.func)
                if term_cfg.history_length > 0:
                    self._histories[group_name][name] = _History(term_cfg.history_length, self.num_envs, self.device)
                    h = term_cfg.history_length
                    term_dim = (
                        (h * int(torch.tensor(term_dim).prod()),) if term_cfg.flatten_history_dim else (h, *term_dim)
                    )
                dims.append(term_dim)
            self._group_obs_term_dim[group_name] = dims
            if self._group_cfgs[group_name].concatenate_terms:
                try:
                    sample = self.compute_group(group_name, update_history=False)
                except RuntimeError as err:
                    raise ValueError(
                        f"ObservationManager: the terms of group '{group_name}' cannot be concatenated"
                        f" (shapes {dict(zip(self.active_terms[group_name], dims))}): {err}"
                    ) from err
                self._group_obs_dim[group_name] = tuple(sample.shape[1:])
            else:
                self._group_obs_dim[group_name] = dims
        self.reset()  # the calls above that measured the terms leave no trace in stateful terms and modifiers


def _column_key(cfg: ObservationTermCfg) -> tuple:
    """What the per-column ops of a term depend on: its noise kind and values, clip, scale."""
    noise = cfg.noise
    if noise is None:
        kind, values = "none", ()
    elif getattr(noise, "operation", None) != "add":
        kind, values = "other", ()
    elif noise.func is noise_model.uniform_noise:
        kind, values = "uniform", (noise.n_min, noise.n_max)
    elif noise.func is noise_model.gaussian_noise:
        kind, values = "gaussian", (noise.mean, noise.std)
    elif noise.func is noise_model.constant_noise:
        kind, values = "constant", (noise.bias,)
    else:
        kind, values = "other", ()
    if any(isinstance(v, torch.Tensor) for v in values):
        kind = "other"  # per-element noise tensors: the term's own path
    scale = ("tensor", id(cfg.scale)) if isinstance(cfg.scale, torch.Tensor) else cfg.scale  # no device read
    return (kind, *values, cfg.clip, scale)


class _ColumnOps:
    """A concatenated group's additive noise, clip and scale as (D,) per-column tensors: four or
    five kernels for the whole group instead of three or four per term (the order per column is
    Isaac Lab's: noise, clip, scale).

    The random numbers are drawn in one call as many as the terms' own draws take together, in the
    same order (term after term, each (num_envs, k) row by row), and gathered into their columns:
    a seeded run draws the same noise as with the per-term path (on the CPU) and leaves the
    generator where that path leaves it.
    """

    def __init__(self, cfgs: list[ObservationTermCfg], widths: list[int], num_envs: int, device):
        gain, offset, low, high, scale = [], [], [], [], []
        self.sample = None  # torch.rand or torch.randn, if some term draws noise
        draws: list[tuple[int, int]] = []  # (first column, width) of the terms that draw, in order
        column = 0
        for cfg, k in zip(cfgs, widths):
            noise = cfg.noise
            g = o = 0.0
            if noise is not None and noise.func is noise_model.uniform_noise:
                g, o, self.sample = noise.n_max - noise.n_min, noise.n_min, torch.rand
            elif noise is not None and noise.func is noise_model.gaussian_noise:
                g, o, self.sample = noise.std, noise.mean, torch.randn
            elif noise is not None:  # constant
                o = noise.bias
            if noise is not None and noise.func is not noise_model.constant_noise:
                draws.append((column, k))
            gain += [g] * k
            offset += [o] * k
            lo, hi = cfg.clip if cfg.clip is not None else (-float("inf"), float("inf"))
            low += [lo] * k
            high += [hi] * k
            s = cfg.scale.flatten().tolist() if isinstance(cfg.scale, torch.Tensor) else [cfg.scale or 1.0]
            scale += [float(v) for v in (s * k if len(s) == 1 else s)]
            column += k

        def tensor(values: list[float]) -> torch.Tensor:
            return torch.tensor(values, dtype=torch.float32, device=device)

        self.gain, self.offset = tensor(gain), tensor(offset)
        self.has_offset = any(o != 0.0 for o in offset)
        self.clip = (tensor(low), tensor(high)) if any(c.clip is not None for c in cfgs) else None
        self.scale = tensor(scale) if any(v != 1.0 for v in scale) else None
        # where each (env, column) finds its number in the one draw (columns without noise: any, gain 0)
        self.num_draws = num_envs * sum(k for _, k in draws)
        where = torch.zeros(num_envs, column, dtype=torch.long)
        start = 0
        for first, k in draws:
            where[:, first : first + k] = start + torch.arange(num_envs * k).view(num_envs, k)
            start += num_envs * k
        self.draw_index = where.to(device)

    def apply(self, obs: torch.Tensor) -> torch.Tensor:
        """Noise, clip and scale ``obs`` (a fresh (num_envs, D) tensor) in place."""
        if self.sample is not None:
            drawn = self.sample(self.num_draws, dtype=obs.dtype, device=obs.device)
            obs.addcmul_(drawn[self.draw_index], self.gain)
        if self.has_offset:
            obs.add_(self.offset)
        if self.clip is not None:
            obs.clamp_(self.clip[0], self.clip[1])
        if self.scale is not None:
            obs.mul_(self.scale)
        return obs
