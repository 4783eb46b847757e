"""Gymnasium spaces from the short specs that env configs use, and torch samples of them.

A config declares a space either as a Gymnasium space or with plain Python values (Isaac Lab's
convention):

=======================  ===================================================
Python spec              Gymnasium space
=======================  ===================================================
``7``, ``[64, 64, 3]``   ``Box(-inf, inf, shape)``
``{2}``                  ``Discrete(2)``
``[{2}, {5}]``           ``MultiDiscrete([2, 5])``
``{"a": 7, "b": {2}}``   ``Dict`` of the above
``(7, {2})``             ``Tuple`` of the above
=======================  ===================================================
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
import torch

SpaceType = gym.spaces.Space | int | set | list | tuple | dict
"""What a config may give as a space (see the module docstring)."""


def spec_to_gym_space(spec: SpaceType) -> gym.spaces.Space:
    """The Gymnasium space a config spec stands for (see the module docstring)."""
    if isinstance(spec, gym.spaces.Space):
        return spec
    if isinstance(spec, bool):
        raise ValueError(f"Unsupported space spec {spec!r}: {_ALLOWED}")
    if isinstance(spec, (int, np.integer)):
        if spec < 0:
            raise ValueError(f"A Box size must be >= 0, got {spec}")
        return gym.spaces.Box(low=-np.inf, high=np.inf, shape=(int(spec),))
    if isinstance(spec, set):
        if len(spec) == 1 and isinstance(next(iter(spec)), int):
            return gym.spaces.Discrete(n=next(iter(spec)))
    elif isinstance(spec, list) and spec:
        if all(isinstance(x, int) and not isinstance(x, bool) for x in spec):
            return gym.spaces.Box(low=-np.inf, high=np.inf, shape=tuple(spec))
        if all(isinstance(x, set) and len(x) == 1 for x in spec):
            return gym.spaces.MultiDiscrete(nvec=[next(iter(x)) for x in spec])
    elif isinstance(spec, tuple):
        return gym.spaces.Tuple([spec_to_gym_space(x) for x in spec])
    elif isinstance(spec, dict):
        return gym.spaces.Dict({k: spec_to_gym_space(v) for k, v in spec.items()})
    raise ValueError(f"Unsupported space spec {spec!r}: {_ALLOWED}")


_ALLOWED = (
    "use a gymnasium space, an int or list of ints (Box), a one-element set (Discrete), a list of "
    "one-element sets (MultiDiscrete), or a dict / tuple of these"
)


def sample_space(
    space: gym.spaces.Space, device: str | torch.device, batch_size: int = -1, fill_value: float | None = None
) -> Any:
    """A sample of ``space`` as torch tensors (a dict / tuple of them for composite spaces).

    With ``batch_size > 0`` every leaf gets a leading batch dimension; ``fill_value`` overwrites the
    random values (e.g. 0 for an initial action buffer).
    """
    if isinstance(space, gym.spaces.Dict):
        return {k: sample_space(s, device, batch_size, fill_value) for k, s in space.items()}
    if isinstance(space, gym.spaces.Tuple):
        return tuple(sample_space(s, device, batch_size, fill_value) for s in space)
    batch = (batch_size,) if batch_size > 0 else ()
    if isinstance(space, gym.spaces.Box):
        shape, dtype = batch + space.shape, torch.float32
    elif isinstance(space, gym.spaces.Discrete):
        shape, dtype = batch + (1,), torch.int64
    elif isinstance(space, gym.spaces.MultiDiscrete):
        shape, dtype = batch + space.shape, torch.int64
    else:
        raise ValueError(
            f"Cannot sample a {type(space).__name__} space as tensors: use Box, Discrete, MultiDiscrete, Dict or Tuple"
        )
    if fill_value is not None:
        return torch.full(shape, fill_value, dtype=dtype, device=device)
    sampled = (gym.vector.utils.batch_space(space, batch_size) if batch_size > 0 else space).sample()
    return torch.as_tensor(np.asarray(sampled), dtype=dtype, device=device).reshape(shape)
