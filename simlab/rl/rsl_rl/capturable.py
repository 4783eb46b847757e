"""torch.distributions inside a CUDA-graph capture.

A CUDA graph records kernels; an operation that reads a value back to the host fails while a graph
is being captured. rsl_rl's Gaussian policy meets two such reads: ``Normal(loc, scale)`` checks its
arguments (``validate_args``, on by default), and ``Normal.sample`` calls ``torch.normal``, which
checks that every ``scale`` is non-negative. Within :func:`capturable_distributions` argument
checks are off and ``Normal.sample`` draws ``loc + scale * randn``, the same distribution drawn by
kernels alone. Outside the block nothing changes; a captured graph replays without Python, so the
block only has to cover the capture. A non-finite policy still stops training: simlab's divergence
guard checks the weights after every update.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

import torch
from torch.distributions import Distribution, Normal

__all__ = ["capturable_distributions"]


def _sample_with_randn(self: Normal, sample_shape: torch.Size = torch.Size()) -> torch.Tensor:  # noqa: B008
    shape = self._extended_shape(sample_shape)
    with torch.no_grad():
        noise = torch.randn(shape, dtype=self.loc.dtype, device=self.loc.device)
        return self.loc.expand(shape) + self.scale.expand(shape) * noise


@contextlib.contextmanager
def capturable_distributions() -> Iterator[None]:
    validate, sample = Distribution._validate_args, Normal.sample
    Distribution.set_default_validate_args(False)
    Normal.sample = _sample_with_randn
    try:
        yield
    finally:
        Distribution.set_default_validate_args(validate)
        Normal.sample = sample
