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

simlab's own files may store the root (the model's free-joint body, the torso) in place of the four
``body_*`` arrays, which are then filled at load by forward kinematics of the humanoid
(:mod:`.body_states`); ``body_names`` stays, and gives the order of the filled bodies:

=========================== ============ ===============================================
``root_positions``          (F, 3)       the root's origin [m]
``root_rotations``          (F, 4)       the root's orientation (w, x, y, z)
``root_linear_velocities``  (F, 3)       optional, with the next: the root origin's velocity [m/s]
``root_angular_velocities`` (F, 3)       the root's angular velocity, world frame [rad/s]
=========================== ============ ===============================================

With root velocities the body velocities are the tree's moving at them and ``dof_velocities`` (a clip
recorded from the simulator); without, finite differences of the body poses (a generated clip).
``write_motion_file(..., body_states=False)`` writes this form where it gives back the body states
within ``POSITION_TOLERANCE`` and ``VELOCITY_TOLERANCE`` (else it says by how much it misses); a file
with body states loads as before.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np

from simlab.robots.humanoid import ASSETS_DIR
from simlab.utils.errors import ConfigError

from .body_states import HumanoidKinematics, finite_difference_velocities

__all__ = ["MOTION_KEYS", "ROOT_KEYS", "body_state_errors", "read_motion_file", "write_motion_file"]

HUMANOID_XML = os.path.join(ASSETS_DIR, "humanoid.xml")

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
BODY_STATE_KEYS = MOTION_KEYS[5:]  # stored all four, or none (then the root's arrays)
ROOT_KEYS = ("root_positions", "root_rotations")
ROOT_VELOCITY_KEYS = ("root_linear_velocities", "root_angular_velocities")  # both or neither
POSITION_TOLERANCE = 1e-5  # [m], and quaternion components: what a compact file may miss by
VELOCITY_TOLERANCE = 1e-4  # [m/s], [rad/s]

# per-frame arrays (the root's too): their trailing shape, from the number of joints D and bodies B
_FRAME_SHAPES = {
    "dof_positions": lambda d, b: (d,),
    "dof_velocities": lambda d, b: (d,),
    "body_positions": lambda d, b: (b, 3),
    "body_rotations": lambda d, b: (b, 4),
    "body_linear_velocities": lambda d, b: (b, 3),
    "body_angular_velocities": lambda d, b: (b, 3),
    "root_positions": lambda d, b: (3,),
    "root_rotations": lambda d, b: (4,),
    "root_linear_velocities": lambda d, b: (3,),
    "root_angular_velocities": lambda d, b: (3,),
}


def read_motion_file(path: str, mjcf: str = HUMANOID_XML) -> dict[str, np.ndarray]:
    """The clip at ``path`` in Isaac Lab's form, checked: every key present, shapes consistent, values
    finite. A file that stores the root in place of the body states gets them by forward kinematics of
    the model ``mjcf``."""
    if not os.path.isfile(path):
        raise FileNotFoundError(f"Motion file not found: {path}")
    try:
        with np.load(path, allow_pickle=False) as data:
            clip = {key: data[key] for key in data.files}
    except (ValueError, OSError) as e:
        raise ValueError(f"{path} is not a motion .npz file ({e}).") from None
    stored = [key for key in BODY_STATE_KEYS if key in clip]
    if 0 < len(stored) < len(BODY_STATE_KEYS):
        raise ConfigError(
            f"Motion file {path} has {stored} but not {[k for k in BODY_STATE_KEYS if k not in stored]}; a motion"
            f" file stores all four body arrays or none (then {list(ROOT_KEYS)}, and forward kinematics fills them)."
        )
    needed = MOTION_KEYS if stored else MOTION_KEYS[:5] + ROOT_KEYS
    missing = [key for key in needed if key not in clip]
    if missing:
        raise ValueError(
            f"Motion file {path} lacks {missing}; a motion file holds {list(MOTION_KEYS)} (or, in place of"
            f" the four body arrays, {list(ROOT_KEYS)})."
        )
    if not stored:  # Isaac Lab's form: the body arrays in place of the root's
        clip.update(_filled_body_states(clip, mjcf, path))
        clip = {key: value for key, value in clip.items() if key not in ROOT_KEYS + ROOT_VELOCITY_KEYS}
    check_motion(clip, path)
    return clip


def _filled_body_states(clip: dict[str, np.ndarray], mjcf: str, where: str) -> dict[str, np.ndarray]:
    """The four body arrays of a clip stored with its root's arrays in their place."""
    velocities = [key for key in ROOT_VELOCITY_KEYS if key in clip]
    if len(velocities) == 1:
        raise ConfigError(
            f"Motion file {where} has {velocities[0]} alone; it stores both {list(ROOT_VELOCITY_KEYS)} or neither."
        )
    _check_frames(clip, [*MOTION_KEYS[3:5], *ROOT_KEYS, *velocities], where)
    if (np.linalg.norm(clip["root_rotations"], axis=-1) < 1e-6).any():
        raise ConfigError(f"{where}: root_rotations holds a zero quaternion.")
    kinematics = HumanoidKinematics(mjcf, _names(clip["dof_names"]), _names(clip["body_names"]), where)
    root = [np.asarray(clip[key], dtype=np.float64) for key in ROOT_KEYS]
    dofs = [np.asarray(clip[key], dtype=np.float64) for key in MOTION_KEYS[3:5]]
    positions, rotations = kinematics.body_poses(*root, dofs[0])
    if velocities:
        root_velocities = [np.asarray(clip[key], dtype=np.float64) for key in velocities]
        linear, angular = kinematics.body_velocities(*root, dofs[0], *root_velocities, dofs[1])
    else:
        linear, angular = finite_difference_velocities(positions, rotations, float(clip["fps"]))
    return {
        key: value.astype(np.float32) for key, value in zip(BODY_STATE_KEYS, (positions, rotations, linear, angular))
    }


def _names(values: np.ndarray | Sequence[str]) -> list[str]:
    return [str(name) for name in np.asarray(values).tolist()]


def check_motion(clip: dict[str, np.ndarray], where: str = "motion") -> None:
    _check_frames(clip, list(MOTION_KEYS[3:]), where)


def _check_frames(clip: dict[str, np.ndarray], keys: list[str], where: str) -> None:
    """fps positive, at least 2 frames, and each of the per-frame arrays ``keys`` of its shape, finite."""
    fps = float(np.asarray(clip["fps"]))
    if not (np.isfinite(fps) and fps > 0):
        raise ValueError(f"{where}: fps must be a positive number, got {clip['fps']!r}.")
    num_dofs, num_bodies = len(clip["dof_names"]), len(clip["body_names"])
    num_frames = np.asarray(clip["dof_positions"]).shape[0] if np.ndim(clip["dof_positions"]) else 0
    if num_frames < 2:
        raise ValueError(f"{where}: a motion needs at least 2 frames, got {num_frames}.")
    for key in keys:
        expected = (num_frames, *_FRAME_SHAPES[key](num_dofs, num_bodies))
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
    body_states: bool = True,
    mjcf: str = HUMANOID_XML,
) -> None:
    """Write a clip in Isaac Lab's format (float32 arrays, string names); checked before writing.

    ``body_states=False`` stores the root of the model ``mjcf`` in place of the body arrays (a fifth of
    the bytes), where forward kinematics gives them back within the tolerances; else a one-line error.
    """
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
    if not body_states:
        clip = _root_form(clip, mjcf, path)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    np.savez_compressed(path, **clip)  # np.load reads it the same; the shipped clips are a third of the size


def _root_form(clip: dict[str, np.ndarray], mjcf: str, where: str) -> dict[str, np.ndarray]:
    """``clip`` with its root's arrays in place of the body states: without root velocities where the body
    velocities are finite differences of the poses, with them where they are the tree's velocities."""
    root_name = HumanoidKinematics(mjcf, _names(clip["dof_names"]), _names(clip["body_names"]), where).root_name
    names = _names(clip["body_names"])
    if root_name not in names:
        raise ConfigError(f"{where}: body_names lack {root_name!r}, the root of {mjcf}, which the compact form stores.")
    root = names.index(root_name)
    compact = {key: value for key, value in clip.items() if key not in BODY_STATE_KEYS}
    compact.update({key: clip[body][:, root] for key, body in zip(ROOT_KEYS, BODY_STATE_KEYS)})
    misses = {}
    for velocities in (False, True):
        if velocities:
            compact.update({key: clip[body][:, root] for key, body in zip(ROOT_VELOCITY_KEYS, BODY_STATE_KEYS[2:])})
        misses[velocities] = body_state_errors(clip, _filled_body_states(compact, mjcf, where))
        position, velocity = misses[velocities]
        if position <= POSITION_TOLERANCE and velocity <= VELOCITY_TOLERANCE:
            return compact
    raise ConfigError(
        f"{where}: forward kinematics of its root and joints misses its body states by {misses[True][0]:.2g} m"
        f" (poses) and {min(misses[False][1], misses[True][1]):.2g} m/s (velocities), more than"
        f" {POSITION_TOLERANCE:g} and {VELOCITY_TOLERANCE:g}: write it with body_states=True."
    )


def body_state_errors(clip: dict[str, np.ndarray], rebuilt: dict[str, np.ndarray]) -> tuple[float, float]:
    """The largest differences between two clips' body poses (positions [m] and quaternion components,
    a quaternion's sign aside) and body velocities (linear [m/s] and angular [rad/s])."""
    sign = np.sign((clip["body_rotations"] * rebuilt["body_rotations"]).sum(-1, keepdims=True) + 1e-12)
    pose = max(
        np.abs(clip["body_positions"] - rebuilt["body_positions"]).max(),
        np.abs(clip["body_rotations"] - sign * rebuilt["body_rotations"]).max(),
    )
    velocity = max(np.abs(clip[key] - rebuilt[key]).max() for key in BODY_STATE_KEYS[2:])
    return float(pose), float(velocity)
