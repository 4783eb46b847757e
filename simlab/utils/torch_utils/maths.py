"""Isaac Sim's ``torch.maths``: scaling to and from [-1, 1], clamping, uniform draws."""

from __future__ import annotations

import torch

from simlab.utils.math import normalize, scale_transform, unscale_transform

__all__ = ["normalize", "scale", "tensor_clamp", "torch_rand_float", "unscale"]


def unscale(x: torch.Tensor, lower: torch.Tensor, upper: torch.Tensor) -> torch.Tensor:
    """Map ``[lower, upper]`` linearly to ``[-1, 1]`` (simlab's ``scale_transform``)."""
    return scale_transform(x, lower, upper)


def scale(x: torch.Tensor, lower: torch.Tensor, upper: torch.Tensor) -> torch.Tensor:
    """Map ``[-1, 1]`` linearly to ``[lower, upper]`` (simlab's ``unscale_transform``)."""
    return unscale_transform(x, lower, upper)


def tensor_clamp(t: torch.Tensor, min_t: torch.Tensor, max_t: torch.Tensor) -> torch.Tensor:
    """``t`` clamped elementwise to ``[min_t, max_t]``."""
    return torch.max(torch.min(t, max_t), min_t)


def torch_rand_float(lower: float, upper: float, shape: tuple[int, ...], device: str | torch.device) -> torch.Tensor:
    """Uniform draws in ``[lower, upper)`` of ``shape``."""
    return (upper - lower) * torch.rand(*shape, device=device) + lower
