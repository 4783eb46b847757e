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


@configclass
class NoiseModelCfg:
    """A noise model: ``class_type(cfg, num_envs, device)`` applied to a whole batch each step."""

    class_type: type = noise_model.NoiseModel
    noise_cfg: NoiseCfg = MISSING
    """The per-step noise."""
    func: Callable[[torch.Tensor], torch.Tensor] | None = None
    """Filled by the env with the built model (Isaac Lab's field); not set by hand."""


@configclass
class NoiseModelWithAdditiveBiasCfg(NoiseModelCfg):
    """Per-step noise plus a per-env bias drawn from ``bias_noise_cfg`` at each reset."""

    class_type: type = noise_model.NoiseModelWithAdditiveBias
    bias_noise_cfg: NoiseCfg = MISSING
    sample_bias_per_component: bool = True
    """A bias per data component (True) or one shared by all components of an env."""
