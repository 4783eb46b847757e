"""Batched torch math for robotics: quaternions, frame transforms, camera projection, 4x4 poses, sampling.

The names and signatures are Isaac Lab's ``isaaclab.utils.math``. Quaternions are ``(w, x, y, z)``,
scalar first, as in Isaac Lab 2.x and MuJoCo. Every function works on
tensors with any number of leading (batch) dimensions, e.g. ``(num_envs, 4)`` or
``(num_envs, num_bodies, 4)``, and broadcasts where shapes allow.
"""

from __future__ import annotations

import functools
import math
from typing import Literal

import numpy as np
import torch

__all__ = [
    "apply_delta_pose",
    "axis_angle_from_quat",
    "combine_frame_transforms",
    "compute_pose_error",
    "constant_tensor",
    "convert_camera_frame_orientation_convention",
    "convert_quat",
    "copysign",
    "create_rotation_matrix_from_view",
    "default_orientation",
    "euler_xyz_from_quat",
    "generate_random_rotation",
    "generate_random_transformation_matrix",
    "generate_random_translation",
    "interpolate_poses",
    "interpolate_rotations",
    "is_identity_pose",
    "make_pose",
    "matrix_from_euler",
    "matrix_from_quat",
    "normalize",
    "orthogonalize_perspective_depth",
    "pose_in_A_to_pose_in_B",
    "pose_inv",
    "project_points",
    "quat_apply",
    "quat_apply_inverse",
    "quat_apply_yaw",
    "quat_box_minus",
    "quat_box_plus",
    "quat_conjugate",
    "quat_error_magnitude",
    "quat_from_angle_axis",
    "quat_from_euler_xyz",
    "quat_from_matrix",
    "quat_inv",
    "quat_mul",
    "quat_rotate",
    "quat_rotate_inverse",
    "quat_slerp",
    "quat_unique",
    "random_orientation",
    "random_yaw_orientation",
    "rigid_body_twist_transform",
    "sample_cylinder",
    "sample_gaussian",
    "sample_log_uniform",
    "sample_triangle",
    "sample_uniform",
    "saturate",
    "scale_transform",
    "skew_symmetric_matrix",
    "subtract_frame_transforms",
    "transform_points",
    "transform_poses_from_frame_A_to_frame_B",
    "unmake_pose",
    "unproject_depth",
    "unscale_transform",
    "wrap_to_pi",
    "yaw_quat",
]

Device = str | torch.device | None


def _check_last_dim(name: str, x: torch.Tensor, size: int) -> None:
    if x.shape[-1] != size:
        raise ValueError(f"{name} must have last dimension {size}, got shape {list(x.shape)}.")


# -- basics ----------------------------------------------------------------------------------------


def normalize(x: torch.Tensor, eps: float = 1e-9) -> torch.Tensor:
    """``x`` divided by its norm over the last dimension (zero vectors stay zero)."""
    return x / x.norm(p=2, dim=-1, keepdim=True).clamp(min=eps)


def wrap_to_pi(angles: torch.Tensor) -> torch.Tensor:
    """Wrap angles (radians) to ``[-pi, pi]``, as MATLAB's ``wrapToPi``.

    Odd positive multiples of pi map to ``pi`` and odd negative multiples to ``-pi`` (so ``pi`` and
    ``-pi`` are kept as given); everything else lands in ``(-pi, pi)``.
    """
    wrapped = torch.remainder(angles + math.pi, 2 * math.pi)
    return torch.where((wrapped == 0) & (angles > 0), math.pi, wrapped - math.pi)


def copysign(mag: float, other: torch.Tensor) -> torch.Tensor:
    """A tensor shaped like ``other`` holding ``|mag|`` with the sign of each element of ``other``."""
    return torch.copysign(torch.full_like(other, abs(mag)), other)


def saturate(x: torch.Tensor, lower: torch.Tensor, upper: torch.Tensor) -> torch.Tensor:
    """Clamp ``x`` to ``[lower, upper]``: tensors that broadcast against ``x`` (numbers too, outside TorchScript)."""
    lower = torch.as_tensor(lower, dtype=x.dtype, device=x.device)
    upper = torch.as_tensor(upper, dtype=x.dtype, device=x.device)
    return torch.maximum(torch.minimum(x, upper), lower)


def scale_transform(x: torch.Tensor, lower: torch.Tensor, upper: torch.Tensor) -> torch.Tensor:
    """Map ``[lower, upper]`` linearly to ``[-1, 1]`` (numbers work as bounds outside TorchScript)."""
    offset = (lower + upper) * 0.5
    return 2 * (x - offset) / (upper - lower)


def unscale_transform(x: torch.Tensor, lower: torch.Tensor, upper: torch.Tensor) -> torch.Tensor:
    """Map ``[-1, 1]`` linearly to ``[lower, upper]`` (inverse of :func:`scale_transform`)."""
    offset = (lower + upper) * 0.5
    return x * (upper - lower) * 0.5 + offset


# -- quaternion algebra ----------------------------------------------------------------------------


def convert_quat(quat: torch.Tensor | np.ndarray, to: Literal["xyzw", "wxyz"] = "xyzw") -> torch.Tensor | np.ndarray:
    """Reorder a quaternion between ``wxyz`` and ``xyzw`` (``to`` names the target order).

    NumPy arrays stay NumPy arrays; anything else is made a torch tensor.
    """
    if to not in ("xyzw", "wxyz"):
        raise ValueError(f"convert_quat: 'to' must be 'xyzw' or 'wxyz', got {to!r}.")
    shift = -1 if to == "xyzw" else 1
    if isinstance(quat, np.ndarray):
        if quat.shape[-1] != 4:
            raise ValueError(f"quat must have last dimension 4, got shape {list(quat.shape)}.")
        return np.roll(quat, shift, axis=-1)
    if not isinstance(quat, torch.Tensor):
        quat = torch.tensor(quat, dtype=torch.float64)
    _check_last_dim("quat", quat, 4)
    return quat.roll(shift, dims=-1)


def quat_mul(q1: torch.Tensor, q2: torch.Tensor) -> torch.Tensor:
    """Hamilton product ``q1 * q2`` (apply ``q2`` first, then ``q1``)."""
    _check_last_dim("q1", q1, 4)
    _check_last_dim("q2", q2, 4)
    if torch.jit.is_scripting():  # TorchScript cannot call the cached tables: the product written out
        w1, x1, y1, z1 = q1.unbind(-1)
        w2, x2, y2, z2 = q2.unbind(-1)
        w = w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2
        x = w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2
        y = w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2
        return torch.stack((w, x, y, z1 * w2 + w1 * z2 + x1 * y2 - y1 * x2), dim=-1)
    # q1 * q2 = L(q1) q2 with L(q1)[i, j] = sign[i, j] q1[index[i, j]]: four kernels, not thirty
    # (each is a launch on the GPU); no matmul, which may run in reduced precision (TF32)
    index, sign = _quat_mul_tables(q1.device, torch.promote_types(q1.dtype, q2.dtype))
    return (q1[..., index] * sign * q2[..., None, :]).sum(dim=-1)


_QUAT_MUL_INDEX = ((0, 1, 2, 3), (1, 0, 3, 2), (2, 3, 0, 1), (3, 2, 1, 0))
_QUAT_MUL_SIGN = ((1, -1, -1, -1), (1, 1, -1, 1), (1, 1, 1, -1), (1, -1, 1, 1))


@functools.lru_cache(maxsize=64)
def _quat_mul_tables(device: torch.device, dtype: torch.dtype) -> tuple[torch.Tensor, torch.Tensor]:
    """Index and sign tables of ``quat_mul``, made once per device and dtype (a step captured as a
    CUDA graph may not copy from the host)."""
    index = torch.tensor(_QUAT_MUL_INDEX, dtype=torch.long, device=device)
    return index, torch.tensor(_QUAT_MUL_SIGN, dtype=dtype, device=device)


def quat_conjugate(q: torch.Tensor) -> torch.Tensor:
    """``(w, -x, -y, -z)``: the inverse rotation for unit quaternions."""
    _check_last_dim("q", q, 4)
    return torch.cat((q[..., :1], -q[..., 1:]), dim=-1)


def quat_inv(q: torch.Tensor, eps: float = 1e-9) -> torch.Tensor:
    """Inverse of a (not necessarily unit) quaternion."""
    return quat_conjugate(q) / (q * q).sum(dim=-1, keepdim=True).clamp(min=eps)


def quat_unique(q: torch.Tensor) -> torch.Tensor:
    """The sign of ``q`` with ``w >= 0`` (``q`` and ``-q`` are the same rotation)."""
    _check_last_dim("q", q, 4)
    return torch.where(q[..., :1] < 0, -q, q)


def quat_apply(quat: torch.Tensor, vec: torch.Tensor) -> torch.Tensor:
    """Rotate ``vec`` (..., 3) by the unit quaternion ``quat`` (..., 4)."""
    return _rotate(quat, vec, inverse=False)


def quat_apply_inverse(quat: torch.Tensor, vec: torch.Tensor) -> torch.Tensor:
    """Rotate ``vec`` by the inverse of the unit quaternion ``quat`` (world -> body frame)."""
    return _rotate(quat, vec, inverse=True)


def _rotate(quat: torch.Tensor, vec: torch.Tensor, inverse: bool) -> torch.Tensor:
    # v' = v + 2 w t + 2 xyz x t with t = xyz x v (no rotation matrix needed); the inverse rotation
    # (conjugate: xyz -> -xyz) flips the sign of the middle term. Four kernels.
    _check_last_dim("quat", quat, 4)
    _check_last_dim("vec", vec, 3)
    shape, numel = vec.shape, vec.numel()
    w, xyz = quat[..., :1], quat[..., 1:]
    xyz, vec = torch.broadcast_tensors(xyz, vec)
    t = torch.linalg.cross(xyz, vec, dim=-1)
    out = torch.addcmul(vec, w, t, value=-2.0 if inverse else 2.0).add_(torch.linalg.cross(xyz, t, dim=-1), alpha=2.0)
    # Isaac Lab returns the vector's shape: a (1, 4) quaternion turns a (3,) vector into a (3,) one
    return out.reshape(shape) if out.dim() > len(shape) and out.numel() == numel else out


# Isaac Lab's older names for the same operations.
quat_rotate = quat_apply
quat_rotate_inverse = quat_apply_inverse


def quat_apply_yaw(quat: torch.Tensor, vec: torch.Tensor) -> torch.Tensor:
    """Rotate ``vec`` by the yaw part of ``quat`` only."""
    return quat_apply(yaw_quat(quat), vec)


# -- conversions -----------------------------------------------------------------------------------


def quat_from_euler_xyz(roll: torch.Tensor, pitch: torch.Tensor, yaw: torch.Tensor) -> torch.Tensor:
    """Quaternion from extrinsic X-Y-Z Euler angles (roll about x, then pitch about y, then yaw about z)."""
    # q = q_z(yaw) * q_y(pitch) * q_x(roll), expanded: each component is a signed sum of two products
    # of three of the half angles' cosines and sines, gathered from one tensor (nine kernels, not 34)
    half = torch.stack(torch.broadcast_tensors(roll, pitch, yaw), dim=-1) * 0.5
    cos_sin = torch.cat((torch.cos(half), torch.sin(half)), dim=-1)  # cr, cp, cy, sr, sp, sy
    if torch.jit.is_scripting():  # TorchScript cannot call the cached tables: the sums written out
        cr, cp, cy, sr, sp, sy = cos_sin.unbind(-1)
        w = cy * cr * cp + sy * sr * sp
        x = cy * sr * cp - sy * cr * sp
        y = cy * cr * sp + sy * sr * cp
        return torch.stack((w, x, y, sy * cr * cp - cy * sr * sp), dim=-1)
    index, sign = _euler_tables(cos_sin.device, cos_sin.dtype)
    return (cos_sin[..., index].prod(dim=-1) * sign).sum(dim=-1)


_EULER_INDEX = (
    ((2, 0, 1), (5, 3, 4)),  # w = cy cr cp + sy sr sp
    ((2, 3, 1), (5, 0, 4)),  # x = cy sr cp - sy cr sp
    ((2, 0, 4), (5, 3, 1)),  # y = cy cr sp + sy sr cp
    ((5, 0, 1), (2, 3, 4)),  # z = sy cr cp - cy sr sp
)
_EULER_SIGN = ((1, 1), (1, -1), (1, 1), (1, -1))


@functools.lru_cache(maxsize=64)
def _euler_tables(device: torch.device, dtype: torch.dtype) -> tuple[torch.Tensor, torch.Tensor]:
    index = torch.tensor(_EULER_INDEX, dtype=torch.long, device=device)
    return index, torch.tensor(_EULER_SIGN, dtype=dtype, device=device)


def euler_xyz_from_quat(
    quat: torch.Tensor, wrap_to_2pi: bool = False
) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """``(roll, pitch, yaw)`` of a unit quaternion (inverse of :func:`quat_from_euler_xyz`).

    Angles are in ``(-pi, pi]`` (pitch in ``[-pi/2, pi/2]``), or in ``[0, 2 pi)`` with ``wrap_to_2pi``.
    At gimbal lock (pitch = +-pi/2) only ``yaw -+ roll`` is defined: roll is then 0 and yaw carries it.
    """
    _check_last_dim("quat", quat, 4)
    w, x, y, z = quat.unbind(-1)
    sin_pitch = (2.0 * (w * y - z * x)).clamp(-1.0, 1.0)
    roll = torch.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = torch.asin(sin_pitch)
    yaw = torch.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    # At the lock both atan2 arguments are ~cos(pitch), i.e. round-off: take yaw from w and z alone
    # (for roll = 0, q = qz(yaw) qy(+-pi/2) has w ~ cos(yaw/2), z ~ sin(yaw/2)).
    locked = (1.0 - sin_pitch.abs()) < 2 * _machine_epsilon(quat.dtype)
    roll = torch.where(locked, torch.zeros_like(roll), roll)
    yaw = torch.where(locked, wrap_to_pi(2.0 * torch.atan2(z, w)), yaw)
    if wrap_to_2pi:
        two_pi = 2 * math.pi
        return roll % two_pi, pitch % two_pi, yaw % two_pi
    return roll, pitch, yaw


def _machine_epsilon(dtype: torch.dtype) -> float:
    """``torch.finfo(dtype).eps`` (which TorchScript lacks) for the floating-point dtypes."""
    if dtype == torch.float64:
        return 2.220446049250313e-16
    if dtype == torch.float16:
        return 0.0009765625
    if dtype == torch.bfloat16:
        return 0.0078125
    return 1.1920928955078125e-07  # float32


def quat_from_angle_axis(angle: torch.Tensor, axis: torch.Tensor) -> torch.Tensor:
    """Quaternion rotating by ``angle`` (...,) radians about ``axis`` (..., 3); the axis is normalized."""
    _check_last_dim("axis", axis, 3)
    half = (angle * 0.5).unsqueeze(-1)
    return torch.cat((torch.cos(half), normalize(axis) * torch.sin(half)), dim=-1)


def axis_angle_from_quat(quat: torch.Tensor, eps: float = 1.0e-6) -> torch.Tensor:
    """Rotation vector (axis * angle, angle in ``[0, pi]``) of a unit quaternion."""
    _check_last_dim("quat", quat, 4)
    quat = quat_unique(quat)  # the short way round
    xyz_norm = torch.linalg.vector_norm(quat[..., 1:], dim=-1)
    half_angle = torch.atan2(xyz_norm, quat[..., 0])
    angle = 2.0 * half_angle
    # sin(angle/2) / angle, with its Taylor expansion near zero to avoid 0/0
    ratio = torch.where(angle.abs() > eps, torch.sin(half_angle) / angle, 0.5 - angle * angle / 48.0)
    return quat[..., 1:] / ratio.unsqueeze(-1)


def quat_error_magnitude(q1: torch.Tensor, q2: torch.Tensor) -> torch.Tensor:
    """Angle (radians, in ``[0, pi]``) of the rotation between ``q1`` and ``q2``."""
    return torch.linalg.vector_norm(axis_angle_from_quat(quat_mul(q1, quat_conjugate(q2))), dim=-1)


def quat_box_minus(q1: torch.Tensor, q2: torch.Tensor) -> torch.Tensor:
    """``q1 [-] q2``: the rotation vector (..., 3) of ``q1 * q2^-1`` (the short way round)."""
    return axis_angle_from_quat(quat_mul(q1, quat_conjugate(q2)))


def quat_box_plus(q: torch.Tensor, delta: torch.Tensor, eps: float = 1.0e-6) -> torch.Tensor:
    """``q [+] delta``: ``q`` turned by the rotation vector ``delta`` (..., 3) in the world frame, ``w >= 0``."""
    _check_last_dim("delta", delta, 3)
    angle = torch.linalg.vector_norm(delta, dim=-1, keepdim=True).clamp(min=eps)
    delta_quat = quat_from_angle_axis(angle.squeeze(-1), delta / angle)
    return quat_unique(quat_mul(delta_quat, q))


def yaw_quat(quat: torch.Tensor) -> torch.Tensor:
    """The rotation about world z only (heading) of ``quat``."""
    _check_last_dim("quat", quat, 4)
    w, x, y, z = quat.unbind(-1)
    yaw = torch.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    zeros = torch.zeros_like(yaw)
    return torch.stack((torch.cos(yaw * 0.5), zeros, zeros, torch.sin(yaw * 0.5)), dim=-1)


def matrix_from_quat(quaternions: torch.Tensor) -> torch.Tensor:
    """Rotation matrix (..., 3, 3) of a quaternion (normalized on the way)."""
    quat = quaternions
    _check_last_dim("quaternions", quat, 4)
    w, x, y, z = quat.unbind(-1)
    two_s = 2.0 / (quat * quat).sum(dim=-1)
    m = torch.stack(
        (
            1 - two_s * (y * y + z * z), two_s * (x * y - z * w), two_s * (x * z + y * w),
            two_s * (x * y + z * w), 1 - two_s * (x * x + z * z), two_s * (y * z - x * w),
            two_s * (x * z - y * w), two_s * (y * z + x * w), 1 - two_s * (x * x + y * y),
        ),
        dim=-1,
    )  # fmt: skip
    return m.reshape(quat.shape[:-1] + (3, 3))


def quat_from_matrix(matrix: torch.Tensor) -> torch.Tensor:
    """Unit quaternion of a rotation matrix (..., 3, 3); the sign is not standardized."""
    if matrix.dim() < 2 or matrix.shape[-1] != 3 or matrix.shape[-2] != 3:
        raise ValueError(f"matrix must have shape (..., 3, 3), got {list(matrix.shape)}.")
    m = matrix.unbind(-1)
    m00, m10, m20 = m[0].unbind(-1)
    m01, m11, m21 = m[1].unbind(-1)
    m02, m12, m22 = m[2].unbind(-1)
    # 2|w|, 2|x|, 2|y|, 2|z|; the largest gives the best-conditioned formula (Shepperd's method)
    q_abs = torch.sqrt(
        torch.stack((1 + m00 + m11 + m22, 1 + m00 - m11 - m22, 1 - m00 + m11 - m22, 1 - m00 - m11 + m22), dim=-1).clamp(
            min=0.0
        )
    )
    # row i is 4 * q_i * (w, x, y, z)
    candidates = torch.stack(
        (
            torch.stack((q_abs[..., 0] ** 2, m21 - m12, m02 - m20, m10 - m01), dim=-1),
            torch.stack((m21 - m12, q_abs[..., 1] ** 2, m10 + m01, m02 + m20), dim=-1),
            torch.stack((m02 - m20, m10 + m01, q_abs[..., 2] ** 2, m12 + m21), dim=-1),
            torch.stack((m10 - m01, m20 + m02, m21 + m12, q_abs[..., 3] ** 2), dim=-1),
        ),
        dim=-2,
    )
    candidates = candidates / (2.0 * q_abs.unsqueeze(-1)).clamp(min=0.1)
    best = q_abs.argmax(dim=-1, keepdim=True)
    quat = candidates.gather(-2, best.unsqueeze(-1).expand(best.shape[:-1] + (1, 4))).squeeze(-2)
    return normalize(quat)


def _axis_rotation_matrix(axis: str, angle: torch.Tensor) -> torch.Tensor:
    """Rotation matrices (..., 3, 3) about the principal axis ``"X"``, ``"Y"`` or ``"Z"``."""
    cos, sin = torch.cos(angle), torch.sin(angle)
    one, zero = torch.ones_like(angle), torch.zeros_like(angle)
    if axis == "X":
        flat = (one, zero, zero, zero, cos, -sin, zero, sin, cos)
    elif axis == "Y":
        flat = (cos, zero, sin, zero, one, zero, -sin, zero, cos)
    elif axis == "Z":
        flat = (cos, -sin, zero, sin, cos, zero, zero, zero, one)
    else:
        raise ValueError(f"axis must be 'X', 'Y' or 'Z', got {axis!r}.")
    return torch.stack(flat, dim=-1).reshape(angle.shape + (3, 3))


def matrix_from_euler(euler_angles: torch.Tensor, convention: str) -> torch.Tensor:
    """Rotation matrices (..., 3, 3) from intrinsic Euler angles (..., 3) in radians.

    ``convention`` is three letters from ``X``, ``Y``, ``Z`` with no axis repeated back to back, e.g.
    ``"XYZ"``: turn about x, then about the new y, then about the newest z (``R = Rx Ry Rz``).
    """
    if euler_angles.dim() == 0 or euler_angles.shape[-1] != 3:
        raise ValueError(f"euler_angles must have shape (..., 3), got {list(euler_angles.shape)}.")
    if len(convention) != 3 or any(c not in "XYZ" for c in convention):
        raise ValueError(f"convention must be three letters from 'X', 'Y', 'Z' (e.g. 'XYZ'), got {convention!r}.")
    if convention[1] in (convention[0], convention[2]):
        raise ValueError(f"convention {convention!r} repeats an axis back to back; e.g. 'XYZ' or 'ZYZ' are valid.")
    first, second, third = (_axis_rotation_matrix(c, a) for c, a in zip(convention, euler_angles.unbind(-1)))
    return first @ second @ third


def skew_symmetric_matrix(vec: torch.Tensor) -> torch.Tensor:
    """The matrix ``[v]x`` with ``[v]x @ u == v x u``: shape (..., 3, 3); a single (3,) vector gives (1, 3, 3)."""
    _check_last_dim("vec", vec, 3)
    if vec.dim() == 1:
        vec = vec.unsqueeze(0)
    x, y, z = vec.unbind(-1)
    zero = torch.zeros_like(x)
    rows = (zero, -z, y, z, zero, -x, -y, x, zero)
    return torch.stack(rows, dim=-1).reshape(vec.shape[:-1] + (3, 3))


# -- frame transforms ------------------------------------------------------------------------------


def combine_frame_transforms(
    t01: torch.Tensor,
    q01: torch.Tensor,
    t12: torch.Tensor | None = None,
    q12: torch.Tensor | None = None,
) -> tuple[torch.Tensor, torch.Tensor]:
    """Compose frame 1 in frame 0 with frame 2 in frame 1: returns ``(t02, q02)`` (frame 2 in frame 0)."""
    q02 = quat_mul(q01, q12) if q12 is not None else q01
    t02 = t01 + quat_apply(q01, t12) if t12 is not None else t01
    return t02, q02


def subtract_frame_transforms(
    t01: torch.Tensor,
    q01: torch.Tensor,
    t02: torch.Tensor | None = None,
    q02: torch.Tensor | None = None,
) -> tuple[torch.Tensor, torch.Tensor]:
    """Express frame 2 in frame 1, given both in frame 0: returns ``(t12, q12)``."""
    q10 = quat_inv(q01)
    q12 = quat_mul(q10, q02) if q02 is not None else q10
    t12 = quat_apply(q10, t02 - t01) if t02 is not None else quat_apply(q10, -t01)
    return t12, q12


def is_identity_pose(pos: torch.Tensor, rot: torch.Tensor) -> bool:
    """Whether every position is (close to) zero and every quaternion (close to) ``(1, 0, 0, 0)``.

    The quaternions are compared by value, so ``(-1, 0, 0, 0)`` does not count as identity.
    """
    identity = torch.zeros_like(rot)
    identity[..., 0] = 1.0
    return bool(torch.allclose(pos, torch.zeros_like(pos)) and torch.allclose(rot, identity))


def rigid_body_twist_transform(
    v0: torch.Tensor, w0: torch.Tensor, t01: torch.Tensor, q01: torch.Tensor
) -> tuple[torch.Tensor, torch.Tensor]:
    """The twist of a rigid body seen at frame 1, given its twist at frame 0 (both in their own frames).

    ``(v0, w0)`` is the linear and angular velocity at the origin of frame 0, in frame 0; frame 1 sits
    at ``t01`` with orientation ``q01`` in frame 0. Returns ``(v1, w1)`` in frame 1:
    ``w1 = R01^T w0`` and ``v1 = R01^T (v0 + w0 x t01)``.
    """
    w1 = quat_apply_inverse(q01, w0)
    v1 = quat_apply_inverse(q01, v0 + torch.linalg.cross(w0, t01, dim=-1))
    return v1, w1


def compute_pose_error(
    t01: torch.Tensor,
    q01: torch.Tensor,
    t02: torch.Tensor,
    q02: torch.Tensor,
    rot_error_type: str = "axis_angle",
) -> tuple[torch.Tensor, torch.Tensor]:
    """Error from a source pose ``(t01, q01)`` to a target pose ``(t02, q02)``, both in frame 0.

    Returns ``(t02 - t01, error)`` where the rotation error is ``q02 * q01^-1`` (world frame), as a
    quaternion (``rot_error_type="quat"``) or a rotation vector (``"axis_angle"``).
    """
    if rot_error_type not in ("quat", "axis_angle"):
        raise ValueError(f"rot_error_type must be 'quat' or 'axis_angle', got '{rot_error_type}'.")
    quat_error = quat_mul(q02, quat_inv(q01))
    pos_error = t02 - t01
    if rot_error_type == "quat":
        return pos_error, quat_error
    return pos_error, axis_angle_from_quat(quat_error)


def apply_delta_pose(
    source_pos: torch.Tensor, source_rot: torch.Tensor, delta_pose: torch.Tensor, eps: float = 1.0e-6
) -> tuple[torch.Tensor, torch.Tensor]:
    """Displace poses by ``delta_pose`` (..., 6): a translation and a world-frame rotation vector.

    Rotation vectors shorter than ``eps`` leave the orientation unchanged.
    """
    _check_last_dim("delta_pose", delta_pose, 6)
    target_pos = source_pos + delta_pose[..., 0:3]
    rot_vec = delta_pose[..., 3:6]
    angle = torch.linalg.vector_norm(rot_vec, dim=-1)
    delta_quat = quat_from_angle_axis(angle, rot_vec)  # normalize() keeps a zero axis at zero
    identity = torch.zeros_like(delta_quat)
    identity[..., 0] = 1.0
    delta_quat = torch.where((angle > eps).unsqueeze(-1), delta_quat, identity)
    return target_pos, quat_mul(delta_quat, source_rot)


def transform_points(
    points: torch.Tensor, pos: torch.Tensor | None = None, quat: torch.Tensor | None = None
) -> torch.Tensor:
    """``R(quat) p + pos`` for points (P, 3) or (N, P, 3); ``pos`` (3,) or (N, 3), ``quat`` (4,) or (N, 4).

    A missing ``pos`` or ``quat`` is no translation or no rotation. The output has the points' shape.
    """
    if points.dim() not in (2, 3) or points.shape[-1] != 3:
        raise ValueError(f"points must have shape (P, 3) or (N, P, 3), got {list(points.shape)}.")
    if pos is not None and (pos.dim() not in (1, 2) or pos.shape[-1] != 3):
        raise ValueError(f"pos must have shape (3,) or (N, 3), got {list(pos.shape)}.")
    if quat is not None and (quat.dim() not in (1, 2) or quat.shape[-1] != 4):
        raise ValueError(f"quat must have shape (4,) or (N, 4), got {list(quat.shape)}.")
    batched = points.dim() == 3
    out = points if batched else points.unsqueeze(0)
    if quat is not None:
        rot = matrix_from_quat(quat.reshape(-1, 4))  # (N or 1, 3, 3)
        out = out @ rot.transpose(-1, -2)
    if pos is not None:
        out = out + pos.reshape(-1, 1, 3)
    return out if batched else out.squeeze(0)


# -- sampling --------------------------------------------------------------------------------------


def _size_tuple(size: int | tuple[int, ...] | list[int] | torch.Size) -> tuple[int, ...]:
    if isinstance(size, int):
        return (size,)
    if isinstance(size, (tuple, list, torch.Size)) and all(isinstance(s, int) for s in size):
        return tuple(size)
    raise TypeError(f"size must be an int or a tuple of ints, got {size!r}.")


def _as_tensor(x: torch.Tensor | float, device: Device) -> torch.Tensor | float:
    # Python numbers stay numbers: torch broadcasts them without a host-to-device copy (which a
    # captured CUDA graph could not hold).
    if isinstance(x, (torch.Tensor, int, float)):
        return x
    return torch.as_tensor(x, dtype=torch.float32, device=device)


def constant_tensor(values, device) -> torch.Tensor:
    """A float32 tensor of fixed numbers (nested lists or tuples), made once per value and device.

    MDP terms read such constants every step; a step captured as a CUDA graph may not copy from the
    host, so they are built on first use and shared after. The tensor must not be written to."""
    return _constant_tensor(_frozen(values), str(device))


def _frozen(values):
    if isinstance(values, (list, tuple)):
        return tuple(_frozen(v) for v in values)
    return float(values)


@functools.lru_cache(maxsize=256)
def _constant_tensor(values: tuple, device: str) -> torch.Tensor:
    return torch.tensor(values, dtype=torch.float32, device=device)


def sample_uniform(
    lower: torch.Tensor | float,
    upper: torch.Tensor | float,
    size: int | tuple[int, ...],
    device: Device = None,
) -> torch.Tensor:
    """Uniform samples in ``[lower, upper)`` of shape ``size``; tensor bounds broadcast against it."""
    shape = _size_tuple(size)
    if isinstance(lower, (int, float)) and isinstance(upper, (int, float)) and lower <= upper:
        return torch.empty(shape, device=device).uniform_(lower, upper)  # one kernel, not four
    lower, upper = _as_tensor(lower, device), _as_tensor(upper, device)
    return torch.rand(shape, device=device) * (upper - lower) + lower


def sample_gaussian(
    mean: torch.Tensor | float, std: torch.Tensor | float, size: int | tuple[int, ...], device: Device = None
) -> torch.Tensor:
    """Normal samples ``mean + std * N(0, 1)`` of shape ``size``."""
    shape = _size_tuple(size)
    mean, std = _as_tensor(mean, device), _as_tensor(std, device)
    return mean + std * torch.randn(shape, device=device)


def sample_log_uniform(
    lower: torch.Tensor | float,
    upper: torch.Tensor | float,
    size: int | tuple[int, ...],
    device: Device = None,
) -> torch.Tensor:
    """Samples whose logarithm is uniform in ``[log lower, log upper)``; bounds must be positive."""
    lower = torch.as_tensor(lower, dtype=torch.float32, device=device)
    upper = torch.as_tensor(upper, dtype=torch.float32, device=device)
    if (lower <= 0).any() or (upper <= 0).any():
        raise ValueError(f"sample_log_uniform needs positive bounds, got lower={lower}, upper={upper}.")
    return torch.exp(sample_uniform(torch.log(lower), torch.log(upper), size, device))


def default_orientation(num: int, device: Device = None) -> torch.Tensor:
    """``num`` identity quaternions ``(1, 0, 0, 0)``."""
    quat = torch.zeros((num, 4), device=device)
    quat[:, 0] = 1.0
    return quat


def random_orientation(num: int, device: Device = None) -> torch.Tensor:
    """``num`` quaternions uniformly distributed over SO(3) (normalized 4D Gaussians)."""
    return normalize(torch.randn((num, 4), device=device))


def random_yaw_orientation(num: int, device: Device = None) -> torch.Tensor:
    """``num`` quaternions with a uniform random yaw in ``[-pi, pi)`` about z."""
    yaw = sample_uniform(-math.pi, math.pi, num, device)
    axis = torch.zeros((num, 3), device=device)
    axis[:, 2] = 1.0
    return quat_from_angle_axis(yaw, axis)


def sample_triangle(lower: float, upper: float, size: int | tuple[int, ...], device: Device = None) -> torch.Tensor:
    """Samples of shape ``size`` from the symmetric triangular distribution on ``[lower, upper]``.

    The density peaks at the midpoint and falls linearly to zero at both ends. (Isaac Lab's version
    maps ``r -> sign(r) sqrt(|r|)``, whose density is highest at the ends; this one is the triangle
    its docstring names.)
    """
    r = 2 * torch.rand(_size_tuple(size), device=device) - 1
    # inverse CDF of the triangle on [-1, 1]: P(|x| < a) = 1 - (1 - a)^2
    r = torch.sign(r) * (1.0 - torch.sqrt(1.0 - r.abs()))
    return (upper - lower) * (r + 1.0) / 2.0 + lower


def sample_cylinder(
    radius: float, h_range: tuple[float, float], size: int | tuple[int, ...], device: Device = None
) -> torch.Tensor:
    """Points (*size, 3) uniform on the side of a z-aligned cylinder of ``radius``, height in ``h_range``."""
    shape = _size_tuple(size)
    angles = (torch.rand(shape, device=device) * 2 - 1) * math.pi
    height = torch.empty(shape, device=device).uniform_(h_range[0], h_range[1])
    return torch.stack((radius * torch.cos(angles), radius * torch.sin(angles), height), dim=-1)


# -- camera projection -----------------------------------------------------------------------------


def _depth_as_batch(depth: torch.Tensor) -> tuple[torch.Tensor, bool, bool]:
    """``depth`` of shape (H, W), (H, W, 1), (N, H, W) or (N, H, W, 1) as (N, H, W).

    Also returns whether it had a batch dimension and a trailing channel of one (a 3D input whose
    last size is 1 is read as (H, W, 1), as Isaac Lab does).
    """
    has_channel = depth.dim() == 4 or (depth.dim() == 3 and depth.shape[-1] == 1)
    if depth.dim() not in (2, 3, 4) or (depth.dim() == 4 and depth.shape[-1] != 1):
        raise ValueError(
            f"depth must have shape (H, W), (H, W, 1), (N, H, W) or (N, H, W, 1), got {list(depth.shape)}."
        )
    batch = depth.squeeze(-1) if has_channel else depth
    is_batched = batch.dim() == 3
    return (batch if is_batched else batch.unsqueeze(0)), is_batched, has_channel


def _intrinsics_as_batch(intrinsics: torch.Tensor) -> torch.Tensor:
    if intrinsics.shape[-2:] != (3, 3) or intrinsics.dim() not in (2, 3):
        raise ValueError(f"intrinsics must have shape (3, 3) or (N, 3, 3), got {list(intrinsics.shape)}.")
    return intrinsics if intrinsics.dim() == 3 else intrinsics.unsqueeze(0)


def orthogonalize_perspective_depth(depth: torch.Tensor, intrinsics: torch.Tensor) -> torch.Tensor:
    """Perspective depth (distance from the optical center) to orthogonal depth (from the image plane).

    ``depth`` is (H, W), (H, W, 1), (N, H, W) or (N, H, W, 1); ``intrinsics`` (3, 3) or (N, 3, 3).
    The output has the shape of ``depth``.
    """
    batch, is_batched, has_channel = _depth_as_batch(depth)
    k = _intrinsics_as_batch(intrinsics).to(batch.dtype)
    height, width = batch.shape[-2:]
    v, u = torch.meshgrid(
        torch.arange(height, device=batch.device, dtype=batch.dtype),
        torch.arange(width, device=batch.device, dtype=batch.dtype),
        indexing="ij",
    )
    fx, fy = k[:, 0, 0].view(-1, 1, 1), k[:, 1, 1].view(-1, 1, 1)
    cx, cy = k[:, 0, 2].view(-1, 1, 1), k[:, 1, 2].view(-1, 1, 1)
    # the ray through pixel (u, v) has direction ((u - cx) / fx, (v - cy) / fy, 1)
    ortho = batch / torch.sqrt(1 + ((u - cx) / fx) ** 2 + ((v - cy) / fy) ** 2)
    if has_channel:
        ortho = ortho.unsqueeze(-1)
    return ortho if is_batched else ortho.squeeze(0)


def unproject_depth(depth: torch.Tensor, intrinsics: torch.Tensor, is_ortho: bool = True) -> torch.Tensor:
    """Point cloud (P, 3) or (N, P, 3) in the camera frame from a depth image, ``P = H * W``.

    ``p = K^-1 (u, v, 1) d`` with ``d`` the orthogonal depth (perspective depth is converted first
    when ``is_ortho`` is False). Points are ordered column by column: index ``u * H + v``, as in
    Isaac Lab.
    """
    if not is_ortho:
        depth = orthogonalize_perspective_depth(depth, intrinsics)
    batch, is_batched, _ = _depth_as_batch(depth)
    k = _intrinsics_as_batch(intrinsics).to(batch.dtype)
    height, width = batch.shape[-2:]
    u, v = torch.meshgrid(
        torch.arange(width, device=batch.device, dtype=batch.dtype),
        torch.arange(height, device=batch.device, dtype=batch.dtype),
        indexing="ij",
    )
    pixels = torch.stack((u.reshape(-1), v.reshape(-1), torch.ones(u.numel(), device=batch.device, dtype=batch.dtype)))
    rays = torch.linalg.inv(k) @ pixels  # (N, 3, P)
    rays = rays / rays[:, 2:3, :]
    d = batch.transpose(1, 2).reshape(batch.shape[0], -1, 1)  # (N, W * H, 1), u-major like the rays
    points = rays.transpose(1, 2) * d
    return points if is_batched else points.squeeze(0)


def project_points(points: torch.Tensor, intrinsics: torch.Tensor) -> torch.Tensor:
    """Pinhole projection of camera-frame points (P, 3) or (N, P, 3) to ``(u, v, depth)``, same shape."""
    if points.dim() not in (2, 3) or points.shape[-1] != 3:
        raise ValueError(f"points must have shape (P, 3) or (N, P, 3), got {list(points.shape)}.")
    batch = points if points.dim() == 3 else points.unsqueeze(0)
    k = _intrinsics_as_batch(intrinsics).to(points.dtype)
    pixels = batch @ k.transpose(-1, -2)  # (N, P, 3): K p for every point
    projected = torch.cat((pixels[..., :2] / pixels[..., 2:3], batch[..., 2:3]), dim=-1)
    return projected if points.dim() == 3 else projected.squeeze(0)


# -- camera frame conventions ----------------------------------------------------------------------

# ``M`` with ``R_opengl = R_convention @ M`` for a camera's world-from-camera rotation: ROS looks
# along +z with +y down (a half turn about x from OpenGL); "world" looks along +x with +z up.
_OPENGL_FROM_CONVENTION = {
    "ros": ((1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0)),
    "world": ((0.0, 0.0, -1.0), (-1.0, 0.0, 0.0), (0.0, 1.0, 0.0)),
}


def convert_camera_frame_orientation_convention(
    orientation: torch.Tensor,
    origin: Literal["opengl", "ros", "world"] = "opengl",
    target: Literal["opengl", "ros", "world"] = "ros",
) -> torch.Tensor:
    """Re-express a camera orientation (..., 4) between the ``opengl``, ``ros`` and ``world`` conventions.

    - ``opengl``: forward -z, up +y (USD cameras);
    - ``ros``: forward +z, up -y;
    - ``world``: forward +x, up +z.

    The result's largest component is positive (the sign :func:`quat_from_matrix` gives).
    """
    for name, value in (("origin", origin), ("target", target)):
        if value not in ("opengl", "ros", "world"):
            raise ValueError(f"{name} must be 'opengl', 'ros' or 'world', got {value!r}.")
    if origin == target:
        return orientation.clone()
    rot = matrix_from_quat(orientation)
    if origin != "opengl":  # to OpenGL: R_gl = R_origin @ M
        rot = rot @ _convention_offset(origin, rot)
    if target != "opengl":  # from OpenGL: R_target = R_gl @ M^T
        rot = rot @ _convention_offset(target, rot).transpose(-1, -2)
    return quat_from_matrix(rot)


def _convention_offset(convention: str, like: torch.Tensor) -> torch.Tensor:
    return torch.tensor(_OPENGL_FROM_CONVENTION[convention], dtype=like.dtype, device=like.device)


def create_rotation_matrix_from_view(
    eyes: torch.Tensor,
    targets: torch.Tensor,
    up_axis: Literal["Y", "Z"] = "Z",
    device: Device = "cpu",
) -> torch.Tensor:
    """World-from-camera rotations (N, 3, 3) of OpenGL cameras at ``eyes`` looking at ``targets`` (N, 3).

    The camera's -z points at the target and its +y is as close to ``up_axis`` as possible.
    """
    if up_axis not in ("Y", "Z"):
        raise ValueError(f"up_axis must be 'Y' or 'Z', got {up_axis!r}.")
    eyes = torch.as_tensor(eyes, dtype=torch.float32, device=device).reshape(-1, 3)
    targets = torch.as_tensor(targets, dtype=torch.float32, device=device).reshape(-1, 3)
    eyes, targets = torch.broadcast_tensors(eyes, targets)
    up = torch.zeros_like(eyes)
    up[:, 1 if up_axis == "Y" else 2] = 1.0
    z_axis = -torch.nn.functional.normalize(targets - eyes, eps=1e-5)
    x_axis = torch.nn.functional.normalize(torch.linalg.cross(up, z_axis, dim=-1), eps=1e-5)
    y_axis = torch.nn.functional.normalize(torch.linalg.cross(z_axis, x_axis, dim=-1), eps=1e-5)
    # looking straight along the up axis leaves x undefined: take it from the camera's y instead
    degenerate = torch.isclose(x_axis, torch.zeros_like(x_axis), atol=5e-3).all(dim=-1, keepdim=True)
    if degenerate.any():
        fallback = torch.nn.functional.normalize(torch.linalg.cross(y_axis, z_axis, dim=-1), eps=1e-5)
        x_axis = torch.where(degenerate, fallback, x_axis)
    return torch.stack((x_axis, y_axis, z_axis), dim=-1)


# -- 4x4 homogeneous poses and interpolation -------------------------------------------------------


def make_pose(pos: torch.Tensor, rot: torch.Tensor) -> torch.Tensor:
    """Homogeneous transforms (..., 4, 4) from positions (..., 3) and rotation matrices (..., 3, 3)."""
    if pos.shape[-1] != 3 or rot.shape[-2:] != (3, 3) or pos.shape[:-1] != rot.shape[:-2]:
        raise ValueError(
            f"make_pose needs pos (..., 3) and rot (..., 3, 3) with the same batch shape, "
            f"got {list(pos.shape)} and {list(rot.shape)}."
        )
    pose = torch.zeros(pos.shape[:-1] + (4, 4), dtype=pos.dtype, device=pos.device)
    pose[..., :3, :3] = rot
    pose[..., :3, 3] = pos
    pose[..., 3, 3] = 1.0
    return pose


def unmake_pose(pose: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """Positions (..., 3) and rotation matrices (..., 3, 3) of homogeneous transforms (..., 4, 4)."""
    return pose[..., :3, 3], pose[..., :3, :3]


def pose_inv(pose: torch.Tensor) -> torch.Tensor:
    """Inverse of rigid transforms (..., 4, 4): ``[R t; 0 1]^-1 = [R^T -R^T t; 0 1]``."""
    pos, rot = unmake_pose(pose)
    rot_t = rot.transpose(-1, -2)
    return make_pose(-(rot_t @ pos.unsqueeze(-1)).squeeze(-1), rot_t)


def pose_in_A_to_pose_in_B(pose_in_A: torch.Tensor, pose_A_in_B: torch.Tensor) -> torch.Tensor:
    """A pose given in frame A, expressed in frame B (``T_B = T_AB @ T_A``)."""
    return pose_A_in_B @ pose_in_A


def transform_poses_from_frame_A_to_frame_B(
    src_poses: torch.Tensor, frame_A: torch.Tensor, frame_B: torch.Tensor
) -> torch.Tensor:
    """Move a pose sequence (T, 4, 4) rigidly so that what was relative to ``frame_B`` is relative to ``frame_A``.

    Each pose becomes ``frame_A @ frame_B^-1 @ pose``.
    """
    return frame_A[None] @ pose_inv(frame_B[None]) @ src_poses


def quat_slerp(q1: torch.Tensor, q2: torch.Tensor, tau: float | torch.Tensor) -> torch.Tensor:
    """Spherical linear interpolation from ``q1`` (tau = 0) to ``q2`` (tau = 1) the short way round.

    Works on batches (..., 4) too; ``tau`` may be a float or a tensor broadcasting against (...,).
    The component order does not matter (``wxyz`` or ``xyzw`` in, the same order out).
    """
    tau = torch.as_tensor(tau, dtype=q1.dtype, device=q1.device).unsqueeze(-1)
    dot = (q1 * q2).sum(dim=-1, keepdim=True)
    q2 = torch.where(dot < 0, -q2, q2)  # the other sign is the shorter arc
    dot = dot.abs().clamp(max=1.0)
    angle = torch.acos(dot)
    sin_angle = torch.sin(angle)
    nearly_equal = sin_angle < 4 * torch.finfo(q1.dtype).eps
    safe_sin = torch.where(nearly_equal, torch.ones_like(sin_angle), sin_angle)
    w1 = torch.where(nearly_equal, 1.0 - tau, torch.sin((1.0 - tau) * angle) / safe_sin)
    w2 = torch.where(nearly_equal, tau, torch.sin(tau * angle) / safe_sin)
    return w1 * q1 + w2 * q2


def interpolate_rotations(R1: torch.Tensor, R2: torch.Tensor, num_steps: int, axis_angle: bool = True) -> torch.Tensor:
    """``num_steps + 1`` rotation matrices (num_steps + 1, 3, 3) evenly spaced from ``R1`` to ``R2`` (both included).

    ``axis_angle`` turns about the fixed axis of ``R2 R1^T``; otherwise quaternion slerp is used
    (the two give the same geodesic).
    """
    if num_steps < 1:
        raise ValueError(f"num_steps must be at least 1, got {num_steps}.")
    taus = torch.arange(num_steps + 1, dtype=R1.dtype, device=R1.device) / num_steps
    if axis_angle:
        delta = axis_angle_from_quat(quat_from_matrix(R2 @ R1.transpose(-1, -2)))
        steps = matrix_from_quat(quat_from_angle_axis(taus * delta.norm(), delta.expand(num_steps + 1, 3)))
        rots = steps @ R1
    else:
        q1, q2 = quat_from_matrix(R1), quat_from_matrix(R2)
        rots = matrix_from_quat(quat_slerp(q1.expand(num_steps + 1, 4), q2.expand(num_steps + 1, 4), taus))
    rots[-1] = R2  # the end is exact
    return rots


def interpolate_poses(
    pose_1: torch.Tensor,
    pose_2: torch.Tensor,
    num_steps: int | None = None,
    step_size: float | None = None,
    perturb: bool = False,
) -> tuple[torch.Tensor, int]:
    """A path of 4x4 poses from ``pose_1`` to ``pose_2`` with ``num_steps`` poses in between.

    Give either ``num_steps`` or ``step_size`` (then ``num_steps = ceil(distance / step_size)``).
    Positions are linear, rotations geodesic; ``perturb`` jitters the inner positions by up to half a
    step. Returns the (num_steps + 2, 4, 4) path and ``num_steps``.
    """
    if (num_steps is None) == (step_size is None):
        raise ValueError("interpolate_poses needs exactly one of num_steps and step_size.")
    pos1, rot1 = unmake_pose(pose_1)
    pos2, rot2 = unmake_pose(pose_2)
    if num_steps is None:
        distance = float((pos2 - pos1).norm())
        if distance == 0.0:
            raise ValueError("interpolate_poses with step_size needs two different positions.")
        num_steps = math.ceil(distance / step_size)
    if num_steps == 0:
        return torch.stack((pose_1, pose_2)), 0
    segments = num_steps + 1
    grid = torch.arange(segments + 1, dtype=pos1.dtype, device=pos1.device)
    if perturb:
        grid[1:-1] += torch.rand(segments - 1, dtype=pos1.dtype, device=pos1.device) - 0.5
    positions = pos1 + (grid / segments).unsqueeze(-1) * (pos2 - pos1)
    positions[-1] = pos2
    rotations = interpolate_rotations(rot1, rot2, segments, axis_angle=True)
    return make_pose(positions, rotations), num_steps


def generate_random_rotation(rot_boundary: float = 2 * math.pi) -> torch.Tensor:
    """A random rotation matrix (3, 3): ``Rz Ry Rx`` with angles uniform in ``[0, rot_boundary)``."""
    angles = torch.rand(3) * rot_boundary
    return matrix_from_euler(angles.flip(0), "ZYX")


def generate_random_translation(pos_boundary: float = 1) -> torch.Tensor:
    """A random translation (3,) uniform in ``[-pos_boundary, pos_boundary)`` per axis."""
    return torch.rand(3) * 2 * pos_boundary - pos_boundary


def generate_random_transformation_matrix(pos_boundary: float = 1, rot_boundary: float = 2 * math.pi) -> torch.Tensor:
    """A random 4x4 rigid transform from :func:`generate_random_rotation` and :func:`generate_random_translation`."""
    return make_pose(generate_random_translation(pos_boundary), generate_random_rotation(rot_boundary))
