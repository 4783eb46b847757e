"""``isaaclab.scene`` of Isaac Lab 3.0: simlab's scene, made from a config whose quaternions are (x, y, z, w)."""

from __future__ import annotations

from simlab import scene as _scene
from simlab.scene import InteractiveSceneCfg, grid_origins
from simlab.v3._order import to_simlab
from simlab.v3.assets import with_v3_assets

__all__ = ["InteractiveScene", "InteractiveSceneCfg", "grid_origins"]


class InteractiveScene(_scene.InteractiveScene):
    """simlab's scene; the (x, y, z, w) configs in ``cfg`` are converted to simlab's order first, and its
    articulations and rigid objects carry Isaac Lab 3.0's asset API (:func:`simlab.v3.assets.with_v3_assets`)."""

    def __init__(self, cfg: InteractiveSceneCfg):
        super().__init__(with_v3_assets(to_simlab(cfg)))
