"""Observation and action noise: configs whose ``func(data, cfg)`` returns a corrupted copy of ``data``,
and noise models that keep per-env state (a bias drawn at reset) for the direct workflow."""

from .noise_cfg import (
    ConstantNoiseCfg,
    GaussianNoiseCfg,
    NoiseCfg,
    NoiseModelCfg,
    NoiseModelWithAdditiveBiasCfg,
    UniformNoiseCfg,
)
from .noise_model import NoiseModel, NoiseModelWithAdditiveBias, constant_noise, gaussian_noise, uniform_noise

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
    "NoiseModel",
    "NoiseModelCfg",
    "NoiseModelWithAdditiveBias",
    "NoiseModelWithAdditiveBiasCfg",
    "UniformNoiseCfg",
    "Unoise",
    "constant_noise",
    "gaussian_noise",
    "uniform_noise",
]
