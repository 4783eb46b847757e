"""Observation modifiers: functions or stateful classes applied to a term's value before noise.

A ``ModifierCfg(func=..., params=...)`` calls ``func(data, **params)``; a ``ModifierBase`` subclass
(``DigitalFilter``, ``Integrator``) keeps state per env and is reset with the env.
"""

from .modifier import DigitalFilter, Integrator, ModifierBase, bias, clip, scale
from .modifier_cfg import DigitalFilterCfg, IntegratorCfg, ModifierCfg
from .modifier_chain import ModifierChain

__all__ = [
    "DigitalFilter",
    "DigitalFilterCfg",
    "Integrator",
    "IntegratorCfg",
    "ModifierBase",
    "ModifierCfg",
    "ModifierChain",
    "bias",
    "clip",
    "scale",
]
