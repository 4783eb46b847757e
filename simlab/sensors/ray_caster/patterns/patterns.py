"""Ray patterns: where each ray of a ray caster starts and where it points, in the sensor's frame."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

if TYPE_CHECKING:
    from .patterns_cfg import GridPatternCfg, LidarPatternCfg, PinholeCameraPatternCfg

ORDERINGS = ("xy", "yx")


def grid_pattern(cfg: GridPatternCfg, device: str) -> tuple[torch.Tensor, torch.Tensor]:
    """Parallel rays on a regular grid spanning ``(-size/2, size/2)`` every ``resolution`` metres.

    Ordering "xy": x varies fastest (inner loop over x); "yx": y varies fastest (Isaac Lab's rule).
    Returns the (R, 3) starts and (R, 3) directions.
    """
    if cfg.ordering not in ORDERINGS:
        raise ValueError(f"GridPatternCfg.ordering must be one of {ORDERINGS}, got '{cfg.ordering}'")
    if cfg.resolution <= 0:
        raise ValueError(f"GridPatternCfg.resolution must be > 0 [m], got {cfg.resolution}")
    if len(cfg.size) != 2 or min(cfg.size) < 0:
        raise ValueError(f"GridPatternCfg.size must be (length, width) >= 0 [m], got {cfg.size}")
    x = torch.arange(-cfg.size[0] / 2, cfg.size[0] / 2 + 1.0e-9, cfg.resolution, device=device)
    y = torch.arange(-cfg.size[1] / 2, cfg.size[1] / 2 + 1.0e-9, cfg.resolution, device=device)
    # torch's "xy" meshgrid puts x on the last axis (fastest when flattened), "ij" puts y there
    grid_x, grid_y = torch.meshgrid(x, y, indexing="xy" if cfg.ordering == "xy" else "ij")
    starts = torch.zeros(grid_x.numel(), 3, device=device)
    starts[:, 0], starts[:, 1] = grid_x.flatten(), grid_y.flatten()
    direction = torch.tensor(list(cfg.direction), dtype=torch.float32, device=device)
    if direction.shape != (3,) or float(direction.norm()) == 0.0:
        raise ValueError(f"GridPatternCfg.direction must be a non-zero 3-vector, got {cfg.direction}")
    directions = (direction / direction.norm()).expand(len(starts), 3).clone()
    return starts, directions


def lidar_pattern(cfg: LidarPatternCfg, device: str) -> tuple[torch.Tensor, torch.Tensor]:
    """Rays from the sensor's origin: ``channels`` elevations across ``vertical_fov_range`` times
    azimuths every ``horizontal_res`` degrees across ``horizontal_fov_range``."""
    if cfg.horizontal_res <= 0:
        raise ValueError(f"LidarPatternCfg.horizontal_res must be > 0 [deg], got {cfg.horizontal_res}")
    vertical = torch.linspace(*cfg.vertical_fov_range, cfg.channels, device=device)
    start, end = cfg.horizontal_fov_range
    full_circle = abs(abs(end - start) - 360.0) < 1.0e-6
    horizontal = torch.arange(start, end if full_circle else end + 1.0e-6, cfg.horizontal_res, device=device)
    elevation, azimuth = torch.meshgrid(torch.deg2rad(vertical), torch.deg2rad(horizontal), indexing="ij")
    directions = torch.stack(
        [elevation.cos() * azimuth.cos(), elevation.cos() * azimuth.sin(), elevation.sin()], dim=-1
    ).reshape(-1, 3)
    return torch.zeros_like(directions), directions


def pinhole_camera_pattern(
    cfg: PinholeCameraPatternCfg, intrinsic_matrices: torch.Tensor, device: str
) -> tuple[torch.Tensor, torch.Tensor]:
    """One ray through the centre of every pixel of each camera's (N, 3, 3) intrinsics, from its origin.

    Unlike the other patterns it takes the intrinsics (Isaac Lab's signature: they may differ per
    camera). Pixels go row by row (index ``v * width + u``); directions are unit vectors in the
    camera's "world" convention frame (x forward, y left, z up). Returns (N, H * W, 3) starts and
    directions.
    """
    v, u = torch.meshgrid(
        torch.arange(cfg.height, device=device, dtype=torch.float32) + 0.5,
        torch.arange(cfg.width, device=device, dtype=torch.float32) + 0.5,
        indexing="ij",
    )
    pixels = torch.stack([u.reshape(-1), v.reshape(-1), torch.ones(u.numel(), device=device)])  # (3, P)
    optical = torch.linalg.inv(intrinsic_matrices.to(device)) @ pixels  # (N, 3, P): x right, y down, z forward
    forward_left_up = torch.stack([optical[:, 2], -optical[:, 0], -optical[:, 1]], dim=-1)  # (N, P, 3)
    directions = forward_left_up / forward_left_up.norm(dim=-1, keepdim=True)
    return torch.zeros_like(directions), directions
