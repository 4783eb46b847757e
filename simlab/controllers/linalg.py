"""Small batched linear algebra in plain torch ops, safe inside a captured CUDA graph.

torch's ``linalg`` solvers may hand small batched matrices to MAGMA or cuSOLVER, which can
synchronize or refuse a stream capture. The controllers solve systems of at most a robot's dof
count (6 to 7 unknowns), for which an unrolled Cholesky factorization is cheap: a few elementwise
kernels per row, each replayed as part of the env step's graph.
"""

from __future__ import annotations

import torch


def solve_spd(a: torch.Tensor, b: torch.Tensor, eps: float = 1e-12) -> torch.Tensor:
    """``x`` with ``a x = b`` for symmetric positive-definite ``a`` (..., n, n) and ``b`` (..., n, k).

    Pivots below ``eps`` are clamped to ``eps`` (a singular ``a`` gives a large but finite ``x``).
    """
    n = a.shape[-1]
    chol = torch.zeros_like(a)
    for j in range(n):
        pivot = (a[..., j, j] - (chol[..., j, :j] ** 2).sum(-1)).clamp_min(eps).sqrt()
        chol[..., j, j] = pivot
        if j + 1 < n:
            below = a[..., j + 1 :, j] - (chol[..., j + 1 :, :j] * chol[..., j, None, :j]).sum(-1)
            chol[..., j + 1 :, j] = below / pivot[..., None]
    y = torch.zeros_like(b)
    for i in range(n):  # chol y = b
        y[..., i, :] = (b[..., i, :] - (chol[..., i, :i, None] * y[..., :i, :]).sum(-2)) / chol[..., i, i, None]
    x = torch.zeros_like(b)
    for i in reversed(range(n)):  # chol^T x = y
        x[..., i, :] = (y[..., i, :] - (chol[..., i + 1 :, i, None] * x[..., i + 1 :, :]).sum(-2)) / chol[
            ..., i, i, None
        ]
    return x


def inverse_spd(a: torch.Tensor, eps: float = 1e-12) -> torch.Tensor:
    """The inverse of symmetric positive-definite ``a`` (..., n, n) (see :func:`solve_spd`)."""
    eye = torch.eye(a.shape[-1], dtype=a.dtype, device=a.device).expand_as(a)
    return solve_spd(a, eye, eps)
