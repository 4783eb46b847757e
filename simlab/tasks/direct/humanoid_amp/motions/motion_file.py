"""Isaac Lab's humanoid motion file: one ``.npz`` per clip.

Keys (frames ``F``, joints ``D``, bodies ``B``; world frame, z up, quaternions ``w, x, y, z``):

=========================== ============ ===============================================
key                         shape        meaning
=========================== ============ ===============================================
``fps``                     ()           frames per second
``dof_names``               (D,)         joint names (strings)
``body_names``              (B,)         body names (strings)
``dof_positions``           (F, D)       joint angles [rad]
``dof_velocities``          (F, D)       joint speeds [rad/s]
``body_positions``          (F, B, 3)    body frame origins [m]
``body_rotations``          (F, B, 4)    body orientations (w, x, y, z)
``body_linear_velocities``  (F, B, 3)    velocities of the body frame origins [m/s]
``body_angular_velocities`` (F, B, 3)    angular velocities, world frame [rad/s]
=========================== ============ ===============================================
"""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np

__all__ = ["MOTION_KEYS", "read_motion_file", "write_motion_file"]

MOTION_KEYS = (
    "fps",
    "dof_names",
    "body_names",
    "dof_positions",
    "dof_velocities",
    "body_positions",
    "body_rotations",
    "body_linear_velocities",
    "body_angular_velocities",
)

# per-frame arrays: their trailing shape, from the number of joints D and bodies B
_FRAME_SHAPES = {
    "dof_positions": lambda d, b: (d,),
    "dof_velocities": lambda d, b: (d,),
    "body_positions": lambda d, b: (b, 3),
    "body_rotations": lambda d, b: (b, 4),
    "body_linear_velocities": lambda d, b: (b, 3),
    "body_angular_velocities": lambda d, b: (b, 3),
}


def read_motion_file(path: str) -> dict[str, np.ndarray]:
    """The clip at ``path``, checked: every key present, shapes consistent, values finite."""
    if not os.path.isfile(path):
        raise FileNotFoundError(f"Motion file not found: {path}")
    try:
        with np.load(path, allow_pickle=False) as data:
            clip = {key: data[key] for key in data.files}
    except (ValueError, OSError) as e:
        raise ValueError(f"{path} is not a motion .npz file ({e}).") from None
    missing = [key for key in MOTION_KEYS if key not in clip]
    if missing:
        raise ValueError(f"Motion file {path} lacks {missing}; a motion file holds {list(MOTION_KEYS)}.")
    check_motion(clip, path)
    return clip


def check_motion(clip: dict[str, np.ndarray], where: str = "motion") -> None:
    fps = float(np.asarray(clip["fps"]))
    if not (np.isfinite(fps) and fps > 0):
        raise ValueError(f"{where}: fps must be a positive number, got {clip['fps']!r}.")
    num_dofs, num_bodies = len(clip["dof_names"]), len(clip["body_names"])
    num_frames = np.asarray(clip["dof_positions"]).shape[0] if np.ndim(clip["dof_positions"]) else 0
    if num_frames < 2:
        raise ValueError(f"{where}: a motion needs at least 2 frames, got {num_frames}.")
    for key, shape in _FRAME_SHAPES.items():
        expected = (num_frames, *shape(num_dofs, num_bodies))
        value = np.asarray(clip[key])
        if value.shape != expected:
            raise ValueError(
                f"{where}: {key} has shape {value.shape}; expected {expected} "
                f"({num_frames} frames, {num_dofs} dof_names, {num_bodies} body_names)."
            )
        if not np.isfinite(value).all():
            raise ValueError(f"{where}: {key} holds non-finite values.")


def write_motion_file(
    path: str,
    *,
    fps: float,
    dof_names: Sequence[str],
    body_names: Sequence[str],
    dof_positions: np.ndarray,
    dof_velocities: np.ndarray,
    body_positions: np.ndarray,
    body_rotations: np.ndarray,
    body_linear_velocities: np.ndarray,
    body_angular_velocities: np.ndarray,
) -> None:
    """Write a clip in Isaac Lab's format (float32 arrays, string names); checked before writing."""
    clip = {
        "fps": np.asarray(fps, dtype=np.float32),
        "dof_names": np.asarray(list(dof_names), dtype=str),
        "body_names": np.asarray(list(body_names), dtype=str),
        "dof_positions": np.asarray(dof_positions, dtype=np.float32),
        "dof_velocities": np.asarray(dof_velocities, dtype=np.float32),
        "body_positions": np.asarray(body_positions, dtype=np.float32),
        "body_rotations": np.asarray(body_rotations, dtype=np.float32),
        "body_linear_velocities": np.asarray(body_linear_velocities, dtype=np.float32),
        "body_angular_velocities": np.asarray(body_angular_velocities, dtype=np.float32),
    }
    check_motion(clip, path)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    np.savez_compressed(path, **clip)  # np.load reads it the same; the shipped clips are a third of the size
