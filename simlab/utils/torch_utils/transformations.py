"""Isaac Sim's ``torch.transformations``: rigid transforms as (quaternion, translation) pairs."""

from __future__ import annotations

import torch

from simlab.utils.math import quat_apply, quat_conjugate, quat_mul

__all__ = ["tf_apply", "tf_combine", "tf_inverse", "tf_vector"]


def tf_inverse(q: torch.Tensor, t: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """The inverse of the transform ``(q, t)``."""
    q_inv = quat_conjugate(q)
    return q_inv, -quat_apply(q_inv, t)


def tf_apply(q: torch.Tensor, t: torch.Tensor, v: torch.Tensor) -> torch.Tensor:
    """The point ``v`` moved by the transform ``(q, t)``."""
    return quat_apply(q, v) + t


def tf_vector(q: torch.Tensor, v: torch.Tensor) -> torch.Tensor:
    """The direction ``v`` turned by ``q``."""
    return quat_apply(q, v)


def tf_combine(
    q1: torch.Tensor, t1: torch.Tensor, q2: torch.Tensor, t2: torch.Tensor
) -> tuple[torch.Tensor, torch.Tensor]:
    """``(q1, t1)`` after ``(q2, t2)``: the transform of frame 2 given in frame 1, in frame 0."""
    return quat_mul(q1, q2), quat_apply(q1, t2) + t1
