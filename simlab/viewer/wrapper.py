"""``ViewerWrapper``: a gymnasium wrapper that shows the env in a live viewer as it steps."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import torch

from simlab.viewer.live import LiveViewer

__all__ = ["ViewerWrapper"]


def _per_env(value: Any) -> torch.Tensor:
    """A reward or done flag per env; multi-agent dicts are summed / or-ed over agents."""
    if isinstance(value, dict):
        values = [torch.as_tensor(v) for v in value.values()]
        if values[0].dtype == torch.bool:
            return torch.stack(values).any(dim=0)
        return torch.stack([v.float() for v in values]).sum(dim=0)
    return torch.as_tensor(value)


class ViewerWrapper(gym.Wrapper):
    """Calls ``viewer.after_step`` after each step; closes the viewer with the env."""

    def __init__(self, env: gym.Env, viewer: LiveViewer):
        super().__init__(env)
        self.viewer = viewer

    def step(self, action):
        obs, reward, terminated, truncated, extras = self.env.step(action)
        done = _per_env(terminated) | _per_env(truncated)
        self.viewer.after_step(_per_env(reward), done)
        return obs, reward, terminated, truncated, extras

    def close(self) -> None:
        self.viewer.close()
        super().close()
