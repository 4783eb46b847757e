"""An ordered list of modifiers applied one after another, e.g. a sensor's output processing."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import torch

from .modifier import ModifierBase
from .modifier_cfg import ModifierCfg


class ModifierChain:
    """Apply ``cfgs`` in order: functions as ``func(data, **params)``, :class:`ModifierBase` classes as instances.

    A class modifier is built at its first call, with the shape of the tensor it receives then (so a
    function before it may change the shape) and, when the chain has a ``sensor``, bound to it with
    ``bind_sensor`` before its first call. ``reset`` resets the built modifiers; ``close`` releases
    them (``close`` on each, once) and the next call builds fresh ones.
    """

    def __init__(self, cfgs: Sequence[ModifierCfg], device: str, sensor: Any = None):
        for i, cfg in enumerate(cfgs):
            if not isinstance(cfg, ModifierCfg):
                raise TypeError(
                    f"ModifierChain entry {i} must be a ModifierCfg (e.g. ModifierCfg(func=clip, params=...)),"
                    f" got {type(cfg).__name__}: {cfg!r}."
                )
        self._cfgs = list(cfgs)
        self._device = device
        self._sensor = sensor
        self._built: dict[int, ModifierBase] = {}  # cfg index -> instance

    @property
    def _instances(self) -> list[ModifierBase]:
        """The class modifiers built so far, in chain order."""
        return [self._built[i] for i in sorted(self._built)]

    def __call__(self, data: torch.Tensor) -> torch.Tensor:
        for i, cfg in enumerate(self._cfgs):
            if isinstance(cfg.func, type) and issubclass(cfg.func, ModifierBase):
                modifier = self._built.get(i)
                if modifier is None:
                    modifier = cfg.func(cfg, tuple(data.shape), device=self._device)
                    if self._sensor is not None and hasattr(modifier, "bind_sensor"):
                        modifier.bind_sensor(self._sensor)
                    self._built[i] = modifier
                data = modifier(data)
            else:
                data = cfg.func(data, **cfg.params)
        return data

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> None:
        for modifier in self._instances:
            modifier.reset(env_ids)

    def close(self) -> None:
        built, self._built = self._instances, {}
        for modifier in built:
            close = getattr(modifier, "close", None)
            if close is not None:
                close()
