"""Piecewise-linear interpolation of a sampled scalar function, batched in torch."""

from __future__ import annotations

import torch


class LinearInterpolation:
    """``f(q)`` from samples ``y = f(x)`` (``x`` ascending): linear between samples, held at the ends.

    ``y`` is ``(n,)``, or ``(n, K)`` for K functions sampled at the same ``x`` (``compute`` then adds
    a last dimension of K: one search serves them all).
    """

    def __init__(self, x: torch.Tensor, y: torch.Tensor, device: str):
        self._x = x.reshape(-1).clone().to(device)
        y = torch.as_tensor(y)
        n = self._x.numel()
        if n == 0:
            raise ValueError("LinearInterpolation needs at least one sample; x is empty.")
        several = y.dim() == 2 and y.shape[0] == n and y.shape[1] > 1  # K functions, one column each
        if not several and y.numel() != n:
            raise ValueError(f"x and y must have the same number of samples, got {n} and {len(y.reshape(-1))}.")
        self._y = (y if several else y.reshape(-1)).clone().to(device)
        if torch.any(self._x[1:] < self._x[:-1]):
            raise ValueError("x must be sorted in ascending order.")
        self._values_per_sample = y.shape[1] if several else 0  # 0: a scalar function
        # One row per segment (start x, start values, slopes), made once: a query is then a clamp, a
        # search, one gather, a subtraction and a multiply-add, five kernels (actuator models run it
        # every physics step), for all K functions at once.
        y2 = self._y.reshape(n, -1)  # (n, K)
        span = (self._x[1:] - self._x[:-1])[:, None]
        slope = torch.where(span > 0, (y2[1:] - y2[:-1]) / torch.where(span > 0, span, 1.0), 0.0)
        segments = torch.cat((self._x[:-1, None], y2[:-1], slope), dim=1)  # (n - 1, 1 + 2K)
        if not len(segments):  # one sample: a constant
            segments = torch.cat((self._x[:, None], y2, torch.zeros_like(y2)), dim=1)
        self._segments = segments
        self._inner_x = self._x[1:-1].contiguous()  # where one segment ends and the next begins

    def compute(self, q: torch.Tensor) -> torch.Tensor:
        """The interpolated values at the query points ``q`` (any shape; the result has the same shape,
        with a last dimension of K for K functions)."""
        # beyond the samples: hold the end values (the clamp also gives the search the contiguous
        # input it needs: a column view of the joint angles would be copied in a hidden kernel)
        clamped = torch.clamp(q.to(self._x.dtype), self._x[0], self._x[-1])
        # (..., 1 + 2K): the segment that ends at or after q
        segment = self._segments[torch.searchsorted(self._inner_x, clamped)]
        k = max(self._values_per_sample, 1)
        x0, y0, slope = segment[..., :1], segment[..., 1 : 1 + k], segment[..., 1 + k :]
        values = torch.addcmul(y0, slope, clamped.unsqueeze(-1) - x0)
        return values if self._values_per_sample else values.squeeze(-1)
