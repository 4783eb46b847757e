"""Observation noise: configs whose ``func(data, cfg)`` returns a corrupted copy of ``data``."""

from .noise_cfg import ConstantNoiseCfg, GaussianNoiseCfg, NoiseCfg, UniformNoiseCfg
from .noise_model import constant_noise, gaussian_noise, uniform_noise

# Isaac Lab's short names.
AdditiveUniformNoiseCfg = UniformNoiseCfg
AdditiveGaussianNoiseCfg = GaussianNoiseCfg
Unoise = UniformNoiseCfg
Gnoise = GaussianNoiseCfg

__all__ = [
    "AdditiveGaussianNoiseCfg",
    "AdditiveUniformNoiseCfg",
    "ConstantNoiseCfg",
    "GaussianNoiseCfg",
    "Gnoise",
    "NoiseCfg",
    "UniformNoiseCfg",
    "Unoise",
    "constant_noise",
    "gaussian_noise",
    "uniform_noise",
]
