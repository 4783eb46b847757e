"""Noise configurations (Isaac Lab's names and fields)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import MISSING
from typing import Literal

import torch

from simlab.utils import configclass

from . import noise_model


@configclass
class NoiseCfg:
    func: Callable[[torch.Tensor, NoiseCfg], torch.Tensor] = MISSING
    operation: Literal["add", "scale", "abs"] = "add"
    """How the sample combines with the data: added, multiplied, or replacing it."""


@configclass
class ConstantNoiseCfg(NoiseCfg):
    func = noise_model.constant_noise
    bias: torch.Tensor | float = 0.0


@configclass
class UniformNoiseCfg(NoiseCfg):
    func = noise_model.uniform_noise
    n_min: torch.Tensor | float = -1.0
    n_max: torch.Tensor | float = 1.0


@configclass
class GaussianNoiseCfg(NoiseCfg):
    func = noise_model.gaussian_noise
    mean: torch.Tensor | float = 0.0
    std: torch.Tensor | float = 1.0
