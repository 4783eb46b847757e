"""Piecewise-linear interpolation of a sampled scalar function, batched in torch."""

from __future__ import annotations

import torch


class LinearInterpolation:
    """``f(q)`` from samples ``y = f(x)`` (``x`` ascending): linear between samples, held at the ends."""

    def __init__(self, x: torch.Tensor, y: torch.Tensor, device: str):
        self._x = x.reshape(-1).clone().to(device)
        self._y = y.reshape(-1).clone().to(device)
        if self._x.numel() == 0:
            raise ValueError("LinearInterpolation needs at least one sample; x is empty.")
        if self._x.numel() != self._y.numel():
            raise ValueError(
                f"x and y must have the same number of samples, got {self._x.numel()} and {self._y.numel()}."
            )
        if torch.any(self._x[1:] < self._x[:-1]):
            raise ValueError("x must be sorted in ascending order.")

    def compute(self, q: torch.Tensor) -> torch.Tensor:
        """The interpolated values at the query points ``q`` (any shape; the result has the same shape)."""
        flat = q.reshape(-1)
        # index of the first sample >= q (searchsorted), and the one before it; both clamped to the ends
        upper = torch.searchsorted(self._x, flat.to(self._x.dtype).contiguous()).clamp(max=self._x.numel() - 1)
        lower = (upper - 1).clamp(min=0)
        x0, x1 = self._x[lower], self._x[upper]
        span = x1 - x0
        weight = torch.where(span > 0, (flat - x0) / torch.where(span > 0, span, torch.ones_like(span)), 0.0)
        weight = weight.clamp(0.0, 1.0)  # beyond the samples: hold the end value
        return (self._y[lower] + weight * (self._y[upper] - self._y[lower])).reshape(q.shape)
