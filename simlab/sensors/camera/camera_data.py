"""What a camera holds after rendering (Isaac Lab's ``CameraData``)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import torch


@dataclass
class CameraData:
    """Images and poses of one camera in every env; N envs, H x W pixels."""

    output: dict[str, torch.Tensor] = field(default_factory=dict)
    """Images by data type, each (N, H, W, C) on the env's device: uint8 ``rgb`` (C=3) and ``rgba`` (C=4);
    float32 ``depth`` / ``distance_to_image_plane`` / ``distance_to_camera`` (C=1, metres); float32 ``normals``
    (C=3, unit, world frame, zero where nothing is hit); ``semantic_segmentation`` and ``instance_segmentation_fast``
    (bodies), ``instance_id_segmentation_fast`` (geoms): uint8 RGBA (C=4) colourised, or int32 ids (C=1)."""
    info: list[dict[str, Any]] | dict[str, Any] = field(default_factory=list)
    """Per camera (Isaac Lab's layout), per data type: ``semantic_segmentation`` and ``instance_segmentation_fast``
    have ``idToLabels`` (body id -> body name), ``instance_id_segmentation_fast`` (geom id -> geom name), keyed
    by colour (``"(r, g, b, a)"``) when colourised; the others None. A ``TiledCamera``'s is one such dict
    for all its cameras (Isaac Lab's tiled layout)."""
    intrinsic_matrices: torch.Tensor | None = None
    """(N, 3, 3) pinhole intrinsics [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] in pixels."""
    pos_w: torch.Tensor | None = None
    """(N, 3) camera positions in the world frame (env origins included)."""
    quat_w_world: torch.Tensor | None = None
    """(N, 4) (w, x, y, z) orientations, world convention (forward +x, up +z)."""
    quat_w_ros: torch.Tensor | None = None
    quat_w_opengl: torch.Tensor | None = None
    image_shape: tuple[int, int] = (0, 0)
    """(height, width)."""
