"""torch.distributions inside a CUDA-graph capture.

A CUDA graph records kernels; an operation that reads a value back to the host fails while a graph
is being captured. rsl_rl's Gaussian policy meets two such reads: ``Normal(loc, scale)`` checks its
arguments (``validate_args``, on by default), and ``Normal.sample`` calls ``torch.normal``, which
checks that every ``scale`` is non-negative. Within :func:`capturable_distributions` argument
checks are off and ``Normal.sample`` draws ``loc + scale * randn``, the same distribution drawn by
kernels alone. Outside the block nothing changes; a captured graph replays without Python, so the
block only has to cover the capture. A non-finite policy still stops training: simlab's divergence
guard checks the weights after every update.

The patch is process-wide while the block runs and leans on ``Normal``'s internals, so it is made
only with the torch release it was checked with (``simlab.utils.versions``); with another,
:func:`capturable_distributions_unsupported` says so and the graphed act and update are not used.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

import torch
from torch.distributions import Distribution, Normal

from simlab.utils.versions import release_mismatch

__all__ = ["capturable_distributions", "capturable_distributions_unsupported"]


def capturable_distributions_unsupported() -> str | None:
    """Why the patch below may not fit the installed torch (None: it is the release it was checked with)."""
    mismatch = release_mismatch("torch")
    return None if mismatch is None else f"{mismatch}: simlab's capturable Normal.sample was checked with that release"


def _sample_with_randn(self: Normal, sample_shape: torch.Size = torch.Size()) -> torch.Tensor:  # noqa: B008
    shape = self._extended_shape(sample_shape)
    with torch.no_grad():
        noise = torch.randn(shape, dtype=self.loc.dtype, device=self.loc.device)
        return self.loc.expand(shape) + self.scale.expand(shape) * noise


@contextlib.contextmanager
def capturable_distributions() -> Iterator[None]:
    reason = capturable_distributions_unsupported()
    if reason is not None:
        raise RuntimeError(reason)
    validate, sample = Distribution._validate_args, Normal.sample
    Distribution.set_default_validate_args(False)
    Normal.sample = _sample_with_randn
    try:
        yield
    finally:
        Distribution.set_default_validate_args(validate)
        Normal.sample = sample
