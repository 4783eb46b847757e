"""Buffers of a ray caster."""

from __future__ import annotations

import torch


class RayCasterData:
    """Shapes use N envs and R rays per sensor; world frame."""

    def __init__(self):
        self.pos_w: torch.Tensor | None = None
        """(N, 3) position of the sensor's body (plus drift)."""
        self.quat_w: torch.Tensor | None = None
        """(N, 4) orientation (w, x, y, z) of the sensor's body."""
        self.ray_hits_w: torch.Tensor | None = None
        """(N, R, 3) where each ray first hits the target geometry; ``inf`` where it hits nothing
        within ``max_distance`` (Isaac Lab's convention)."""
