"""Types and configs shared by the environments."""

from __future__ import annotations

from typing import Literal

import torch

from simlab.utils import configclass


@configclass
class ViewerCfg:
    """Where the viewer camera (``env.render()``) looks from and at."""

    eye: tuple[float, float, float] = (7.5, 7.5, 7.5)
    """Camera position [m], in the frame given by ``origin_type``."""
    lookat: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """Point the camera looks at [m], in the same frame."""
    cam_prim_path: str = "/OmniverseKit_Persp"
    """Kept for Isaac Lab configs; simlab renders with a MuJoCo free camera."""
    resolution: tuple[int, int] = (640, 480)
    """Rendered image size (width, height) in pixels."""
    origin_type: Literal["world", "env", "asset_root", "asset_body"] = "world"
    """Frame of ``eye`` and ``lookat``: the world, env ``env_index``'s origin, or an asset's root."""
    env_index: int = 0
    """The environment that is rendered (each environment is its own MuJoCo world)."""
    asset_name: str | None = None
    """For ``origin_type="asset_root"``: the scene entity the camera follows."""
    body_name: str | None = None
    """For ``origin_type="asset_body"``: the body of ``asset_name`` the camera follows."""


VecEnvObs = dict[str, torch.Tensor | dict[str, torch.Tensor]]
"""Observations of all envs: group name -> tensor (num_envs, ...) or dict of such tensors."""

VecEnvStepReturn = tuple[VecEnvObs, torch.Tensor, torch.Tensor, torch.Tensor, dict]
"""``(obs, reward, terminated, truncated, extras)``, each with the env dimension first."""
