"""Camera helpers (Isaac Lab's ``isaaclab.sensors.camera.utils``): images as pictures a person can look
at (several envs tiled into one PNG), and point clouds from depth images."""

from __future__ import annotations

import math
import os

import numpy as np
import torch


def displayable(images: torch.Tensor) -> torch.Tensor:
    """(N, H, W, C) camera images as uint8 RGB (N, H, W, 3): colours as they are, depth and ids as grey
    levels (near is bright; inf, nothing hit, is black)."""
    images = images.detach().cpu()
    if images.dtype == torch.uint8:
        return images[..., :3] if images.shape[-1] >= 3 else images[..., :1].expand(*images.shape[:-1], 3)
    values = images[..., :1].float()
    finite = torch.isfinite(values) & (values >= 0)
    if not finite.any():
        return torch.zeros(*images.shape[:-1], 3, dtype=torch.uint8)
    low, high = values[finite].min(), values[finite].max()
    scaled = 1.0 - (values - low) / (high - low).clamp(min=1e-6)
    if images.dtype.is_floating_point is False:  # segmentation ids: bright is a larger id, -1 black
        scaled = 1.0 - scaled
    grey = torch.where(finite, 0.15 + 0.85 * scaled, 0.0)
    return (255 * grey).round().to(torch.uint8).expand(*images.shape[:-1], 3)


def tile_images(images: torch.Tensor, columns: int | None = None, gap: int = 2) -> np.ndarray:
    """One (rows * H, columns * W, 3) uint8 picture of N images (N, H, W, C), row by row, with
    ``gap`` white pixels between tiles."""
    if images.ndim != 4:
        raise ValueError(f"Expected camera images of shape (N, H, W, C), got {tuple(images.shape)}")
    pictures = displayable(images).numpy()
    n, h, w, _ = pictures.shape
    columns = columns or math.ceil(math.sqrt(n))
    rows = math.ceil(n / columns)
    sheet = np.full((rows * (h + gap) - gap, columns * (w + gap) - gap, 3), 255, dtype=np.uint8)
    for index, picture in enumerate(pictures):
        row, col = divmod(index, columns)
        sheet[row * (h + gap) : row * (h + gap) + h, col * (w + gap) : col * (w + gap) + w] = picture
    return sheet


def save_images_to_file(images: torch.Tensor, file_path: str) -> None:
    """Save (N, H, W, C) images as one tiled PNG (Isaac Lab's helper; float RGB in [0, 1] is scaled to 0-255)."""
    from simlab.utils.optional import require

    iio = require("imageio.v3")  # the "render" extra; a clear install hint when missing

    if images.dtype.is_floating_point and images.shape[-1] in (3, 4):
        images = (images.clamp(0.0, 1.0) * 255).round().to(torch.uint8)
    folder = os.path.dirname(file_path)
    if folder:
        os.makedirs(folder, exist_ok=True)
    iio.imwrite(file_path, tile_images(images))


def create_pointcloud_from_depth(
    intrinsic_matrix: torch.Tensor | np.ndarray,
    depth: torch.Tensor | np.ndarray,
    keep_invalid: bool = False,
    position: torch.Tensor | np.ndarray | None = None,
    orientation: torch.Tensor | np.ndarray | None = None,
    device: torch.device | str | None = None,
) -> torch.Tensor | np.ndarray:
    """Points (P, 3) seen in one depth image (H, W) or (H, W, 1) of ``distance_to_image_plane``.

    The points are in the camera's frame, or in the world frame when the camera's ``position`` and
    ``orientation`` (ROS convention, ``data.quat_w_ros``) are given. Pixels without a finite depth
    (nothing hit) are dropped unless ``keep_invalid``. A NumPy depth gives NumPy points, as Isaac Lab's.
    """
    from simlab.utils.array import convert_to_torch
    from simlab.utils.math import transform_points, unproject_depth

    is_numpy = isinstance(depth, np.ndarray)
    depth = convert_to_torch(depth, dtype=torch.float32, device=device or ("cpu" if is_numpy else None))
    device = depth.device
    intrinsic_matrix = convert_to_torch(intrinsic_matrix, dtype=torch.float32, device=device)
    if position is not None:
        position = convert_to_torch(position, dtype=torch.float32, device=device)
    if orientation is not None:
        orientation = convert_to_torch(orientation, dtype=torch.float32, device=device)
    points = transform_points(unproject_depth(depth, intrinsic_matrix), position, orientation)
    if not keep_invalid:
        points = points[torch.isfinite(points).all(dim=1)]
    return points.detach().cpu().numpy() if is_numpy else points
