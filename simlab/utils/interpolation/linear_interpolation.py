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
        # One row per interval between samples, and one before the first and after the last sample
        # (flat: the end values), as (intercept, slope), made once in float64: a query is then a clamp
        # into the samples' range (which also gives the search the contiguous input it needs), one
        # search, one gather and one multiply-add, four kernels (actuator models run it every physics
        # step). Row k holds for x[k-1] < q <= x[k] (searchsorted's left side).
        x64 = self._x.double()
        y64 = self._y.double().reshape(len(x64), -1)  # (n, K)
        span = (x64[1:] - x64[:-1])[:, None]
        slope = torch.where(span > 0, (y64[1:] - y64[:-1]) / torch.where(span > 0, span, 1.0), 0.0)
        intercept = y64[:-1] - slope * x64[:-1, None]
        flat = torch.zeros_like(y64[:1])
        self._rows64 = torch.cat(
            (torch.cat((y64[:1], intercept, y64[-1:])), torch.cat((flat, slope, flat))), dim=1
        )  # (n + 1, 2K): intercepts, then slopes
        self._tables: dict[torch.dtype, tuple[torch.Tensor, torch.Tensor]] = {}

    def compute(self, q: torch.Tensor) -> torch.Tensor:
        """The interpolated values at the query points ``q`` (any shape; the result has the same shape,
        with a last dimension of K for K functions, and ``q``'s floating dtype)."""
        if not q.is_floating_point():
            q = q.to(self._x.dtype)
        x, rows = self._table(q.dtype)
        q = torch.clamp(q, x[0], x[-1])  # held at the end values beyond the samples, even at +-inf
        row = rows[torch.searchsorted(x, q)]  # (..., 2K)
        k = max(self._values_per_sample, 1)
        values = torch.addcmul(row[..., :k], row[..., k:], q.unsqueeze(-1))
        return values if self._values_per_sample else values.squeeze(-1)

    def _table(self, dtype: torch.dtype) -> tuple[torch.Tensor, torch.Tensor]:
        """The samples and rows in ``dtype`` (made at the first query of that dtype)."""
        table = self._tables.get(dtype)
        if table is None:
            table = self._tables[dtype] = (self._x.to(dtype).contiguous(), self._rows64.to(dtype))
        return table
