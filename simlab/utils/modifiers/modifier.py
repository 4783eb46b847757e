"""Modifier functions and stateful modifiers."""

from __future__ import annotations

from collections.abc import Sequence

import torch

from simlab.utils.env_mask import env_mask, masked_copy_


def scale(data: torch.Tensor, multiplier: float) -> torch.Tensor:
    return data * multiplier


def clip(data: torch.Tensor, bounds: tuple[float | None, float | None]) -> torch.Tensor:
    return data.clip(min=bounds[0], max=bounds[1])


def bias(data: torch.Tensor, value: float) -> torch.Tensor:
    return data + value


class ModifierBase:
    """A modifier with per-env state: ``__call__(data)`` (advances the state), ``peek(data)`` (the
    same output, state unchanged: an observation computed twice in a step advances it once) and
    ``reset(env_ids)``."""

    def __init__(self, cfg, data_dim: tuple[int, ...], device: str):
        self._cfg = cfg
        self._data_dim = data_dim
        self._device = device

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> None:
        raise NotImplementedError

    def __call__(self, data: torch.Tensor) -> torch.Tensor:
        raise NotImplementedError

    def peek(self, data: torch.Tensor) -> torch.Tensor:
        raise NotImplementedError


class DigitalFilter(ModifierBase):
    """Linear IIR/FIR filter with coefficients ``A`` (feedback) and ``B`` (feedforward)."""

    def __init__(self, cfg, data_dim: tuple[int, ...], device: str):
        super().__init__(cfg, data_dim, device)
        if cfg.A is None or cfg.B is None or len(cfg.B) == 0:
            raise ValueError("DigitalFilterCfg needs coefficient lists A (may be empty) and B (not empty)")
        self.A = torch.tensor(cfg.A, dtype=torch.float32, device=device)
        self.B = torch.tensor(cfg.B, dtype=torch.float32, device=device)
        self.x_n = torch.zeros(*data_dim, len(cfg.B), device=device)
        self.y_n = torch.zeros(*data_dim, len(cfg.A), device=device)

    def reset(self, env_ids=None) -> None:
        mask = env_mask(env_ids, self.x_n.shape[0], self.x_n.device)
        masked_copy_(self.x_n, mask, 0.0)
        masked_copy_(self.y_n, mask, 0.0)

    def __call__(self, data: torch.Tensor) -> torch.Tensor:
        y, x_n, y_n = self._next(data)
        # State is updated in place: a graphed env step reads and writes fixed buffers.
        self.x_n.copy_(x_n)
        self.y_n.copy_(y_n)
        return y

    def peek(self, data: torch.Tensor) -> torch.Tensor:
        return self._next(data)[0]

    def _next(self, data: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        x_n = torch.roll(self.x_n, shifts=1, dims=-1)
        x_n[..., 0] = data
        y = torch.sum(x_n * self.B, dim=-1)
        y_n = self.y_n
        if len(self.A):
            y = y - torch.sum(self.y_n * self.A, dim=-1)
            y_n = torch.roll(self.y_n, shifts=1, dims=-1)
            y_n[..., 0] = y
        return y, x_n, y_n


class Integrator(ModifierBase):
    """Trapezoidal integration of the data over time."""

    def __init__(self, cfg, data_dim: tuple[int, ...], device: str):
        super().__init__(cfg, data_dim, device)
        self.integral = torch.zeros(data_dim, device=device)
        self.y_prev = torch.zeros(data_dim, device=device)

    def reset(self, env_ids=None) -> None:
        mask = env_mask(env_ids, self.integral.shape[0], self.integral.device)
        masked_copy_(self.integral, mask, 0.0)
        masked_copy_(self.y_prev, mask, 0.0)

    def __call__(self, data: torch.Tensor) -> torch.Tensor:
        self.integral += (data + self.y_prev) / 2 * self._cfg.dt
        self.y_prev[:] = data
        return self.integral.clone()

    def peek(self, data: torch.Tensor) -> torch.Tensor:
        return self.integral + (data + self.y_prev) / 2 * self._cfg.dt
