"""Noise functions: ``func(data, cfg) -> data`` with the sample added, multiplied or substituted; and
noise models (Isaac Lab's ``NoiseModel``, ``NoiseModelWithAdditiveBias``), which keep per-env state."""

from __future__ import annotations

import torch

from simlab.utils.env_mask import env_mask, masked_copy_


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


# -- noise models: per-env state across steps ---------------------------------------------------------


class NoiseModel:
    """Applies ``noise_model_cfg.noise_cfg`` to a ``(num_envs, ...)`` batch; keeps no state."""

    def __init__(self, noise_model_cfg, num_envs: int, device: str):
        self._noise_model_cfg = noise_model_cfg
        self._num_envs = num_envs
        self._device = device

    def reset(self, env_ids=None) -> None:
        """Redraw per-env state where ``env_ids`` (ids, a bool mask, or None for all) selects."""

    def __call__(self, data: torch.Tensor) -> torch.Tensor:
        return self._noise_model_cfg.noise_cfg.func(data, self._noise_model_cfg.noise_cfg)


class NoiseModelWithAdditiveBias(NoiseModel):
    """Per-step noise plus a bias drawn from ``bias_noise_cfg`` per env at reset and constant within
    the episode (OpenAI's model of a miscalibrated sensor or actuator).

    With ``sample_bias_per_component`` each component of the data gets its own bias, sized from the
    first batch the model sees. Resets draw for every env and keep the draw where the mask is set,
    so a reset inside a graphed step has fixed shapes.
    """

    def __init__(self, noise_model_cfg, num_envs: int, device: str):
        super().__init__(noise_model_cfg, num_envs, device)
        self._bias_noise_cfg = noise_model_cfg.bias_noise_cfg
        self._per_component = noise_model_cfg.sample_bias_per_component
        self._bias = torch.zeros((num_envs, 1), device=device)
        self._sized = not self._per_component

    @property
    def bias(self) -> torch.Tensor:
        """(num_envs, 1) or (num_envs, num_components): the bias of each env's present episode."""
        return self._bias

    def reset(self, env_ids=None) -> None:
        mask = env_mask(env_ids, self._num_envs, self._device)
        masked_copy_(self._bias, mask, self._bias_noise_cfg.func(self._bias, self._bias_noise_cfg))

    def __call__(self, data: torch.Tensor) -> torch.Tensor:
        if not self._sized:  # the first batch tells the number of components; draw every env's bias
            self._bias = torch.zeros((self._num_envs, data.shape[-1]), device=self._device)
            self._sized = True
            self.reset()
        return super().__call__(data) + self._bias
