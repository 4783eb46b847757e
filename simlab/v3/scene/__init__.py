"""``isaaclab.scene`` of Isaac Lab 3.0: simlab's scene, made from a config whose quaternions are (x, y, z, w)."""

from __future__ import annotations

from simlab import scene as _scene
from simlab.scene import InteractiveSceneCfg, grid_origins
from simlab.v3._order import to_simlab

__all__ = ["InteractiveScene", "InteractiveSceneCfg", "grid_origins"]


class InteractiveScene(_scene.InteractiveScene):
    """simlab's scene; the (x, y, z, w) configs in ``cfg`` are converted to simlab's order first."""

    def __init__(self, cfg: InteractiveSceneCfg):
        super().__init__(to_simlab(cfg))
