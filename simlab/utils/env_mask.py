"""Envs selected by a boolean mask, and the per-env state that resets by it.

Inside an env step, the envs that finished travel down as a ``(num_envs,)`` bool mask, never as a
list of ids: a mask has a fixed shape, so resetting by it needs no ``nonzero()``, no host read and
no branch on a device value, and the same code runs eagerly and inside a CUDA graph. Random draws
are made for every row and kept only where the mask is set. Isaac Lab's index API
(``reset(env_ids)``, ``_reset_idx(env_ids)``) turns ids into a mask at its boundary (``env_mask``).

Each component that keeps per-env buffers (an asset, a manager, a term, the env's counters)
declares them once in a :class:`PerEnvState` with what a reset writes into them, and resets them
with one call: nothing has to find them later.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from typing import Any

import torch

EnvIds = Sequence[int] | torch.Tensor | slice | None

ResetValue = float | int | bool | Callable[[], torch.Tensor] | None
"""What a reset writes into a buffer: a constant, a function drawing values for *every* row
(kept where the mask is set), or None (the owner resets it itself)."""


def env_mask(env_ids: EnvIds, num_envs: int, device: torch.device | str) -> torch.Tensor:
    """``env_ids`` (None for all, a bool mask, ids, a slice) as a ``(num_envs,)`` bool mask."""
    if isinstance(env_ids, torch.Tensor) and env_ids.dtype == torch.bool:
        if env_ids.shape != (num_envs,):
            raise ValueError(f"an env mask must have shape ({num_envs},), got {tuple(env_ids.shape)}")
        return env_ids.to(device)
    mask = torch.zeros(num_envs, dtype=torch.bool, device=device)
    if env_ids is None:
        return mask.fill_(True)
    if isinstance(env_ids, slice):
        mask[env_ids] = True
        return mask
    if not isinstance(env_ids, torch.Tensor):
        env_ids = torch.as_tensor(list(env_ids), dtype=torch.long)
    mask[env_ids.to(device=device, dtype=torch.long)] = True
    return mask


def env_ids_in_order(env_ids: EnvIds, num_envs: int, device: torch.device | str) -> torch.Tensor:
    """``env_ids`` as a 1-D long tensor of ids: given ids in their order (values given with them match
    it, repeats kept), a bool mask, slice or None as the ascending ids they select (a host read)."""
    if env_ids is None or isinstance(env_ids, slice) or is_mask(env_ids):
        return env_mask(env_ids, num_envs, device).nonzero().flatten()
    return torch.as_tensor(env_ids, dtype=torch.long, device=device).reshape(-1)


def is_mask(env_ids: EnvIds) -> bool:
    return isinstance(env_ids, torch.Tensor) and env_ids.dtype == torch.bool


def rows(mask: torch.Tensor, like: torch.Tensor) -> torch.Tensor:
    """``mask`` shaped to broadcast over the rows of ``like`` ((N,) -> (N, 1, ..., 1))."""
    return mask.view(-1, *([1] * (like.dim() - 1)))


def masked_copy_(dst: torch.Tensor, mask: torch.Tensor, values: torch.Tensor | float) -> torch.Tensor:
    """``dst[i] = values[i]`` where ``mask[i]``, in place, with fixed shapes; returns ``dst``."""
    if not isinstance(values, torch.Tensor):
        return dst.masked_fill_(rows(mask, dst), values)
    return torch.where(rows(mask, dst), values.to(dst.dtype), dst, out=dst)


def takes_env_mask(func: Callable) -> Callable:
    """Mark an event or curriculum term function that accepts a bool mask as ``env_ids``.

    Managers pass such terms the ``(num_envs,)`` mask of the envs concerned; other terms get ids
    (``mask.nonzero()``: a host read, so a step that calls them is not graphed). Class terms set
    the class attribute ``takes_env_mask = True`` instead.
    """
    func.takes_env_mask = True
    return func


def host_read_when(check: Callable[[Any, dict[str, Any]], str | None]) -> Callable[[Callable], Callable]:
    """Mark a mask-taking term that, for some params, still reads the device back to the host (so a
    step that runs it is not graphed): ``check(env, params)`` says why, or None when it does not.
    Class terms define a static method ``host_read(env, params)`` instead."""

    def mark(func: Callable) -> Callable:
        func.host_read = check
        return func

    return mark


def term_host_read(func: Callable, env: Any, params: dict[str, Any]) -> str | None:
    """Why the term ``func`` with ``params`` reads the device back to the host (None if it does not)."""
    check = getattr(func, "host_read", None)
    return None if check is None else check(env, params)


def term_env_ids(func: Callable, mask: torch.Tensor) -> torch.Tensor | None:
    """What to pass a term as ``env_ids``: the mask if it takes one, else the ids (None if none)."""
    if getattr(func, "takes_env_mask", False):
        return mask
    ids = mask.nonzero().flatten()
    return ids if len(ids) else None


class PerEnvState:
    """The per-env buffers of one component, declared in one place, reset by mask.

    Usage::

        self.state = PerEnvState(num_envs, device)
        self.episode_sums = self.state.zeros("episode_sums", (num_terms,))
        self.timer = self.state.add("timer", torch.zeros(num_envs), reset=lambda: draw_all_rows())
        ...
        self.state.reset(mask)    # every declared buffer, rows where mask is set
    """

    def __init__(self, num_envs: int, device: torch.device | str):
        self.num_envs = num_envs
        self.device = torch.device(device)
        self._buffers: dict[str, tuple[torch.Tensor, ResetValue]] = {}

    def add(self, name: str, tensor: torch.Tensor, reset: ResetValue = 0) -> torch.Tensor:
        """Declare ``tensor`` (leading dimension ``num_envs``); returns it."""
        if tensor.shape[:1] != (self.num_envs,):
            raise ValueError(f"per-env buffer '{name}' must have {self.num_envs} rows, got shape {tuple(tensor.shape)}")
        if name in self._buffers:
            raise ValueError(f"per-env buffer '{name}' is declared twice")
        self._buffers[name] = (tensor, reset)
        return tensor

    def zeros(self, name: str, shape: tuple[int, ...] = (), dtype: torch.dtype = torch.float32, reset: ResetValue = 0):
        """Declare a new buffer of zeros ``(num_envs, *shape)``; returns it."""
        return self.add(name, torch.zeros(self.num_envs, *shape, dtype=dtype, device=self.device), reset)

    def reset(self, mask: torch.Tensor) -> None:
        """Write each buffer's reset value into the rows where ``mask`` is set."""
        for tensor, value in self._buffers.values():
            if value is None:
                continue
            masked_copy_(tensor, mask, value() if callable(value) else value)

    def __getitem__(self, name: str) -> torch.Tensor:
        return self._buffers[name][0]

    def __iter__(self) -> Iterator[tuple[str, torch.Tensor]]:
        return ((name, tensor) for name, (tensor, _) in self._buffers.items())

    def __len__(self) -> int:
        return len(self._buffers)
