"""Seeding of every random number generator a run touches."""

from __future__ import annotations

import os
import random

import numpy as np

__all__ = ["configure_seed", "set_seed"]


def set_seed(seed: int, torch_deterministic: bool = False) -> int:
    """Seed python's ``random``, numpy and torch (CPU and CUDA); ``seed=-1`` draws a random seed.

    Returns the seed used, so that a run seeded with -1 can be logged and reproduced.
    """
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise TypeError(f"seed must be an int (-1 for a random one), got {type(seed).__name__}: {seed!r}.")
    seed = int(seed)
    if seed == -1:
        seed = int(np.random.SeedSequence().entropy % 2**31)
    if not 0 <= seed < 2**32:
        raise ValueError(f"seed must be -1 or in [0, 2**32), got {seed}.")
    import torch  # lazy: keep `import simlab.utils` light

    random.seed(seed)
    np.random.seed(seed)
    torch.manual_seed(seed)  # also seeds every CUDA device
    os.environ["PYTHONHASHSEED"] = str(seed)  # for child processes
    if torch_deterministic:
        os.environ["CUBLAS_WORKSPACE_CONFIG"] = ":4096:8"
        torch.backends.cudnn.benchmark = False
        torch.backends.cudnn.deterministic = True
        torch.use_deterministic_algorithms(True)
    return seed


configure_seed = set_seed  # Isaac Lab's name
