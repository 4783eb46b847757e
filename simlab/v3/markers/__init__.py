"""``isaaclab.markers`` of Isaac Lab 3.0: simlab's markers, ``visualize(orientations=...)`` in (x, y, z, w).

The marker configs carry no orientation and are simlab's (:mod:`simlab.markers.config` is
``simlab.v3.markers.config``)."""

from __future__ import annotations

from typing import Any

import numpy as np
import torch

from simlab import markers as _markers
from simlab.v3.markers import config  # noqa: F401  (the submodule, as in Isaac Lab)

__all__ = ["VisualizationMarkers", "VisualizationMarkersCfg", "config"]

VisualizationMarkersCfg = _markers.VisualizationMarkersCfg


class VisualizationMarkers(_markers.VisualizationMarkers):
    """simlab's markers; the orientations 3.0 code gives are (x, y, z, w)."""

    def visualize(
        self,
        translations: torch.Tensor | np.ndarray | None = None,
        orientations: torch.Tensor | np.ndarray | None = None,
        scales: torch.Tensor | np.ndarray | None = None,
        marker_indices: torch.Tensor | np.ndarray | list[int] | None = None,
    ) -> None:
        if orientations is not None:
            orientations = orientations[..., [3, 0, 1, 2]]  # (x, y, z, w) -> (w, x, y, z), tensor or array
        super().visualize(translations, orientations, scales, marker_indices)


def __getattr__(name: str) -> Any:
    return getattr(_markers, name)
