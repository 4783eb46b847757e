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
        # One row per segment (start x, start y, slope), made once: a query is then a clamp, a search,
        # one gather and a multiply-add, five kernels (actuator models run it every physics step).
        span = self._x[1:] - self._x[:-1]
        slope = torch.where(span > 0, (self._y[1:] - self._y[:-1]) / torch.where(span > 0, span, 1.0), 0.0)
        segments = torch.stack((self._x[:-1], self._y[:-1], slope), dim=1)
        self._segments = segments if len(segments) else torch.stack((self._x, self._y, torch.zeros_like(self._x)), 1)
        self._inner_x = self._x[1:-1].contiguous()  # where one segment ends and the next begins

    def compute(self, q: torch.Tensor) -> torch.Tensor:
        """The interpolated values at the query points ``q`` (any shape; the result has the same shape)."""
        # beyond the samples: hold the end values
        clamped = torch.clamp(q.to(self._x.dtype), self._x[0], self._x[-1])
        # (..., 3): the segment that ends at or after q
        segment = self._segments[torch.searchsorted(self._inner_x, clamped)]
        x0, y0, slope = segment.unbind(-1)
        return torch.addcmul(y0, slope, clamped - x0)
