"""Noise functions: ``func(data, cfg) -> data`` with the sample added, multiplied or substituted."""

from __future__ import annotations

import torch


def _combine(data: torch.Tensor, sample: torch.Tensor, operation: str) -> torch.Tensor:
    if operation == "add":
        return data + sample
    if operation == "scale":
        return data * sample
    if operation == "abs":
        return sample
    raise ValueError(f"Unknown noise operation '{operation}'; allowed: 'add', 'scale', 'abs'")


def _on(value, data: torch.Tensor):
    return value.to(data.device) if isinstance(value, torch.Tensor) else value


def constant_noise(data: torch.Tensor, cfg) -> torch.Tensor:
    bias = _on(cfg.bias, data)
    return _combine(data, torch.zeros_like(data) + bias, cfg.operation)


def uniform_noise(data: torch.Tensor, cfg) -> torch.Tensor:
    n_min, n_max = _on(cfg.n_min, data), _on(cfg.n_max, data)
    return _combine(data, torch.rand_like(data) * (n_max - n_min) + n_min, cfg.operation)


def gaussian_noise(data: torch.Tensor, cfg) -> torch.Tensor:
    mean, std = _on(cfg.mean, data), _on(cfg.std, data)
    return _combine(data, mean + std * torch.randn_like(data), cfg.operation)
