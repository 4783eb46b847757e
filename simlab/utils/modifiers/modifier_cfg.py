"""Modifier configurations (Isaac Lab's names and fields)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import MISSING
from typing import Any

from simlab.utils import configclass

from .modifier import DigitalFilter, Integrator


@configclass
class ModifierCfg:
    func: Callable | type = MISSING
    """``func(data, **params)``, or a ``ModifierBase`` subclass built with ``(cfg, data_dim, device)``."""
    params: dict[str, Any] = dict()


@configclass
class DigitalFilterCfg(ModifierCfg):
    """``y[n] = sum(B[k] x[n-k]) - sum(A[k] y[n-1-k])`` per env and element."""

    func: type = DigitalFilter
    A: list[float] = MISSING
    B: list[float] = MISSING


@configclass
class IntegratorCfg(ModifierCfg):
    """Trapezoidal integral of the data over time, with step ``dt``."""

    func: type = Integrator
    dt: float = MISSING
