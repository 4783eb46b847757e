"""Commands: goals the policy follows (e.g. a base velocity), resampled after a random time.

A ``CommandTerm`` holds ``command`` (num_envs, ...) and resamples it per env when its timer runs
out; it may track metrics (logged at resets as ``Metrics/<term>/<metric>``).

A *user command* overrides the sampled one for chosen envs: a person steering a velocity policy
from a live viewer, or a script. ``enable_user_command()`` adds it to the step (a device tensor and a
per-env mask, applied with one masked copy after the term updates its command: nothing is read
back, so a graphed step applies it too); ``set_user_command`` and ``release_user_command`` write
those tensors in place between steps.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import torch

from simlab.utils.debug_vis import DebugVisHooks
from simlab.utils.env_mask import EnvIds, env_mask, is_mask, masked_copy_, rows
from simlab.utils.errors import ConfigError

from .manager_base import ManagerBase, ManagerTermBase, cfg_items, format_table
from .manager_term_cfg import CommandTermCfg

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv


class CommandTerm(ManagerTermBase, DebugVisHooks):
    """Subclasses implement ``command``, ``_resample_command``, ``_update_command``, ``_update_metrics``.

    ``_resample_command(env_ids)`` gets ids (Isaac Lab's convention: eager, a host read per step)
    or, when the class sets ``resamples_by_mask = True``, a ``(num_envs,)`` bool mask, with which the
    term draws for every env and keeps the draws where the mask is set (a graphable step).
    """

    resamples_by_mask: bool = False

    def __init__(self, cfg: CommandTermCfg, env: ManagerBasedRLEnv):
        super().__init__(cfg, env)
        if cfg.debug_vis and not self.has_debug_vis_implementation:
            raise ConfigError(
                f"{type(cfg).__name__}.debug_vis=True is not supported by simlab: {type(self).__name__} draws no"
                " debug visualization. Set debug_vis=False (override: env.commands.<term>.debug_vis=false), or"
                " implement _set_debug_vis_impl and _debug_vis_callback in the term (simlab.markers)."
            )
        self.metrics: dict[str, torch.Tensor] = {}
        self.time_left = torch.zeros(self.num_envs, device=self.device)
        self.command_counter = torch.zeros(self.num_envs, dtype=torch.long, device=self.device)
        self._user_command: torch.Tensor | None = None  # (num_envs, ...) like ``command``, once enabled
        self._user_mask: torch.Tensor | None = None  # (num_envs,) bool: the envs that follow it
        self.set_debug_vis(cfg.debug_vis)

    @property
    def command(self) -> torch.Tensor:
        raise NotImplementedError

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> dict[str, float]:
        mask = env_mask(env_ids, self.num_envs, self.device)
        count = mask.sum().clamp(min=1)
        extras = {}
        for name, value in self.metrics.items():
            extras[name] = (value * rows(mask, value)).sum() / count
            masked_copy_(value, mask, 0.0)
        masked_copy_(self.command_counter, mask, 0)
        self._resample(mask)
        self._apply_user_command()
        return extras

    def compute(self, dt: float) -> None:
        self._update_metrics()
        self.time_left -= dt
        self._resample(self.time_left <= 0.0)
        self._update_command()
        self._apply_user_command()

    # -- a user command instead of the sampled one ----------------------------------------------

    @property
    def user_command_enabled(self) -> bool:
        return self._user_command is not None

    def enable_user_command(self) -> None:
        """Let :meth:`set_user_command` override the command of chosen envs (one masked copy per step
        from now on; none before). Call it before the env's step is captured as a CUDA graph."""
        if self._user_command is not None:
            return
        name = type(self).__name__
        if getattr(self._env, "step_is_graphed", False):
            raise RuntimeError(
                f"{name}.enable_user_command() came after the env's step was captured as a CUDA graph, which"
                " would never apply it: enable it before the first steps (or set sim.use_cuda_graph=False)"
            )
        first, second = self.command, self.command
        if first.data_ptr() != second.data_ptr():
            raise TypeError(f"{name} computes a new command tensor on each read: it has no command to override")
        self._user_command = torch.zeros_like(first)
        self._user_mask = torch.zeros(self.num_envs, dtype=torch.bool, device=self.device)

    def set_user_command(self, command: Sequence[float] | torch.Tensor, env_ids: EnvIds = None) -> None:
        """Give the envs ``env_ids`` (ids, a bool mask, None for all) ``command`` (one row, or one per
        env) instead of their sampled command, from the next step on, until released. Writes device
        tensors in place: call it between steps, graphed or not."""
        if self._user_command is None:
            raise RuntimeError(f"{type(self).__name__}: call enable_user_command() before set_user_command()")
        values = torch.as_tensor(command, dtype=self._user_command.dtype, device=self.device)
        shape, row = tuple(self._user_command.shape), tuple(self._user_command.shape[1:])
        if tuple(values.shape) not in (shape, row):
            raise ValueError(f"a user command has shape {row} (or {shape}, one per env), got {tuple(values.shape)}")
        mask = env_mask(env_ids, self.num_envs, self.device)
        masked_copy_(self._user_command, mask, values.expand(shape))
        self._user_mask |= mask

    def release_user_command(self, env_ids: EnvIds = None) -> None:
        """Back to sampled commands for the envs ``env_ids`` that had a user command: each draws a new
        one in the next step."""
        if self._user_mask is None:
            return
        released = env_mask(env_ids, self.num_envs, self.device) & self._user_mask
        self._user_mask &= ~released
        masked_copy_(self.time_left, released, 0.0)  # resampled at the next compute

    def _apply_user_command(self) -> None:
        if self._user_command is not None:
            masked_copy_(self.command, self._user_mask, self._user_command)

    def _resample(self, mask: torch.Tensor | Sequence[int]) -> None:
        """New commands and timers for the envs where ``mask`` is set. Isaac Lab's terms call it
        with env ids (its in-hand goal term on success): those are turned into the mask."""
        if not is_mask(mask):
            mask = env_mask(mask, self.num_envs, self.device)
        lower, upper = self.cfg.resampling_time_range
        masked_copy_(self.time_left, mask, torch.empty(self.num_envs, device=self.device).uniform_(lower, upper))
        if self.resamples_by_mask:
            self._resample_command(mask)
        else:
            ids = mask.nonzero().flatten()  # an index-based term: data-dependent ids, eager only
            if len(ids):
                self._resample_command(ids)
        self.command_counter += mask

    def _resample_command(self, env_ids: torch.Tensor) -> None:
        raise NotImplementedError

    def _update_command(self) -> None:
        raise NotImplementedError

    def _update_metrics(self) -> None:
        raise NotImplementedError

    def _debug_vis_simulation(self):
        return self._env.sim


class CommandManager(ManagerBase):
    def __init__(self, cfg: object, env: ManagerBasedRLEnv):
        self._terms: dict[str, CommandTerm] = {}
        self._term_cfgs: list[tuple[str, CommandTermCfg]] = []
        super().__init__(cfg, env)

    def __str__(self) -> str:
        rows = [(i, name, type(term).__name__) for i, (name, term) in enumerate(self._terms.items())]
        return format_table("Active Command Terms", ["Index", "Name", "Type"], rows)

    @property
    def active_terms(self) -> list[str]:
        return [name for name, _ in self._term_cfgs]

    @property
    def has_debug_vis_implementation(self) -> bool:
        return any(term.has_debug_vis_implementation for term in self._terms.values())

    def set_debug_vis(self, debug_vis: bool) -> bool:
        """Show or hide the markers of every term that draws itself; False when none does."""
        drawn = [term.set_debug_vis(debug_vis) for term in self._terms.values()]
        return any(drawn)

    def get_command(self, name: str) -> torch.Tensor:
        return self.get_term(name).command

    def get_term(self, name: str) -> CommandTerm:
        if name not in self._terms:
            raise KeyError(f"No command term '{name}'; command terms: {self.active_terms}")
        return self._terms[name]

    def get_active_iterable_terms(self, env_idx: int) -> Sequence[tuple[str, Sequence[float]]]:
        return [(name, term.command[env_idx].cpu().tolist()) for name, term in self._terms.items()]

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> dict[str, torch.Tensor]:
        extras = {}
        for name, term in self._terms.items():
            for metric, value in term.reset(env_ids).items():
                extras[f"Metrics/{name}/{metric}"] = value
        return extras

    def compute(self, dt: float) -> None:
        for term in self._terms.values():
            term.compute(dt)

    def graph_blockers(self) -> list[str]:
        return [
            f"command term '{name}' resamples by env ids; set resamples_by_mask = True on {type(term).__name__}"
            for name, term in self._terms.items()
            if not term.resamples_by_mask and type(term).compute is CommandTerm.compute
        ]

    def _prepare_terms(self) -> None:
        for name, term_cfg in cfg_items(self.cfg):
            if not isinstance(term_cfg, CommandTermCfg):
                raise TypeError(
                    f"CommandManager: term '{name}' must be a CommandTermCfg, got {type(term_cfg).__name__}"
                )
            self._term_cfgs.append((name, term_cfg))

    def _on_sim_started(self) -> None:
        for name, term_cfg in self._term_cfgs:
            try:
                term_cfg.validate()
                self._terms[name] = term_cfg.class_type(term_cfg, self._env)
            except (ValueError, KeyError, TypeError) as err:
                raise self._term_error(name, str(err)) from err
