"""Batched torch math for robotics: quaternions, frame transforms, sampling.

Quaternions are ``(w, x, y, z)``, scalar first, as in Isaac Lab and MuJoCo. Every function works on
tensors with any number of leading (batch) dimensions, e.g. ``(num_envs, 4)`` or
``(num_envs, num_bodies, 4)``, and broadcasts where shapes allow.
"""

from __future__ import annotations

import math

import torch

__all__ = [
    "axis_angle_from_quat",
    "combine_frame_transforms",
    "convert_quat",
    "default_orientation",
    "euler_xyz_from_quat",
    "matrix_from_quat",
    "normalize",
    "quat_apply",
    "quat_apply_inverse",
    "quat_apply_yaw",
    "quat_conjugate",
    "quat_error_magnitude",
    "quat_from_angle_axis",
    "quat_from_euler_xyz",
    "quat_from_matrix",
    "quat_inv",
    "quat_mul",
    "quat_rotate",
    "quat_rotate_inverse",
    "quat_unique",
    "random_orientation",
    "random_yaw_orientation",
    "sample_gaussian",
    "sample_log_uniform",
    "sample_uniform",
    "saturate",
    "scale_transform",
    "subtract_frame_transforms",
    "unscale_transform",
    "wrap_to_pi",
    "yaw_quat",
]

Device = str | torch.device | None


def _check_last_dim(name: str, x: torch.Tensor, size: int) -> None:
    if x.shape[-1] != size:
        raise ValueError(f"{name} must have last dimension {size}, got shape {tuple(x.shape)}.")


# -- basics ----------------------------------------------------------------------------------------


def normalize(x: torch.Tensor, eps: float = 1e-9) -> torch.Tensor:
    """``x`` divided by its norm over the last dimension (zero vectors stay zero)."""
    return x / x.norm(p=2, dim=-1, keepdim=True).clamp(min=eps)


def wrap_to_pi(angles: torch.Tensor) -> torch.Tensor:
    """Wrap angles (radians) to ``(-pi, pi]``."""
    wrapped = torch.remainder(angles, 2 * math.pi)
    return torch.where(wrapped > math.pi, wrapped - 2 * math.pi, wrapped)


def saturate(x: torch.Tensor, lower: torch.Tensor | float, upper: torch.Tensor | float) -> torch.Tensor:
    """Clamp ``x`` to ``[lower, upper]`` (bounds may be tensors that broadcast against ``x``)."""
    lower = torch.as_tensor(lower, dtype=x.dtype, device=x.device)
    upper = torch.as_tensor(upper, dtype=x.dtype, device=x.device)
    return torch.maximum(torch.minimum(x, upper), lower)


def scale_transform(x: torch.Tensor, lower: torch.Tensor | float, upper: torch.Tensor | float) -> torch.Tensor:
    """Map ``[lower, upper]`` linearly to ``[-1, 1]``."""
    offset = (lower + upper) * 0.5
    return 2 * (x - offset) / (upper - lower)


def unscale_transform(x: torch.Tensor, lower: torch.Tensor | float, upper: torch.Tensor | float) -> torch.Tensor:
    """Map ``[-1, 1]`` linearly to ``[lower, upper]`` (inverse of :func:`scale_transform`)."""
    offset = (lower + upper) * 0.5
    return x * (upper - lower) * 0.5 + offset


# -- quaternion algebra ----------------------------------------------------------------------------


def convert_quat(quat: torch.Tensor, to: str = "xyzw") -> torch.Tensor:
    """Reorder a quaternion between ``wxyz`` and ``xyzw`` (``to`` names the target order)."""
    _check_last_dim("quat", quat, 4)
    if to == "xyzw":
        return quat.roll(-1, dims=-1)
    if to == "wxyz":
        return quat.roll(1, dims=-1)
    raise ValueError(f"convert_quat: 'to' must be 'xyzw' or 'wxyz', got {to!r}.")


def quat_mul(q1: torch.Tensor, q2: torch.Tensor) -> torch.Tensor:
    """Hamilton product ``q1 * q2`` (apply ``q2`` first, then ``q1``)."""
    _check_last_dim("q1", q1, 4)
    _check_last_dim("q2", q2, 4)
    w1, x1, y1, z1 = q1.unbind(-1)
    w2, x2, y2, z2 = q2.unbind(-1)
    return torch.stack(
        (
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ),
        dim=-1,
    )


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
    _check_last_dim("quat", quat, 4)
    _check_last_dim("vec", vec, 3)
    w, xyz = quat[..., :1], quat[..., 1:]
    xyz, vec = torch.broadcast_tensors(xyz, vec)
    # v' = v + w t + xyz x t with t = 2 xyz x v (no rotation matrix needed)
    t = 2.0 * torch.linalg.cross(xyz, vec, dim=-1)
    return vec + w * t + torch.linalg.cross(xyz, t, dim=-1)


def quat_apply_inverse(quat: torch.Tensor, vec: torch.Tensor) -> torch.Tensor:
    """Rotate ``vec`` by the inverse of the unit quaternion ``quat`` (world -> body frame)."""
    return quat_apply(quat_conjugate(quat), vec)


# Isaac Lab's older names for the same operations.
quat_rotate = quat_apply
quat_rotate_inverse = quat_apply_inverse


def quat_apply_yaw(quat: torch.Tensor, vec: torch.Tensor) -> torch.Tensor:
    """Rotate ``vec`` by the yaw part of ``quat`` only."""
    return quat_apply(yaw_quat(quat), vec)


# -- conversions -----------------------------------------------------------------------------------


def quat_from_euler_xyz(roll: torch.Tensor, pitch: torch.Tensor, yaw: torch.Tensor) -> torch.Tensor:
    """Quaternion from extrinsic X-Y-Z Euler angles (roll about x, then pitch about y, then yaw about z)."""
    cr, sr = torch.cos(roll * 0.5), torch.sin(roll * 0.5)
    cp, sp = torch.cos(pitch * 0.5), torch.sin(pitch * 0.5)
    cy, sy = torch.cos(yaw * 0.5), torch.sin(yaw * 0.5)
    # q = q_z(yaw) * q_y(pitch) * q_x(roll), expanded
    return torch.stack(
        (
            cy * cr * cp + sy * sr * sp,
            cy * sr * cp - sy * cr * sp,
            cy * cr * sp + sy * sr * cp,
            sy * cr * cp - cy * sr * sp,
        ),
        dim=-1,
    )


def euler_xyz_from_quat(
    quat: torch.Tensor, wrap_to_2pi: bool = False
) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """``(roll, pitch, yaw)`` of a unit quaternion (inverse of :func:`quat_from_euler_xyz`).

    Angles are in ``(-pi, pi]`` (pitch in ``[-pi/2, pi/2]``), or in ``[0, 2 pi)`` with ``wrap_to_2pi``.
    """
    _check_last_dim("quat", quat, 4)
    w, x, y, z = quat.unbind(-1)
    roll = torch.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = torch.asin((2.0 * (w * y - z * x)).clamp(-1.0, 1.0))
    yaw = torch.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    if wrap_to_2pi:
        two_pi = 2 * math.pi
        return roll % two_pi, pitch % two_pi, yaw % two_pi
    return roll, pitch, yaw


def quat_from_angle_axis(angle: torch.Tensor, axis: torch.Tensor) -> torch.Tensor:
    """Quaternion rotating by ``angle`` (...,) radians about ``axis`` (..., 3); the axis is normalized."""
    _check_last_dim("axis", axis, 3)
    half = (angle * 0.5).unsqueeze(-1)
    return torch.cat((torch.cos(half), normalize(axis) * torch.sin(half)), dim=-1)


def axis_angle_from_quat(quat: torch.Tensor, eps: float = 1.0e-6) -> torch.Tensor:
    """Rotation vector (axis * angle, angle in ``[0, pi]``) of a unit quaternion."""
    _check_last_dim("quat", quat, 4)
    quat = quat_unique(quat)  # the short way round
    xyz_norm = quat[..., 1:].norm(dim=-1)
    half_angle = torch.atan2(xyz_norm, quat[..., 0])
    angle = 2.0 * half_angle
    # sin(angle/2) / angle, with its Taylor expansion near zero to avoid 0/0
    ratio = torch.where(angle.abs() > eps, torch.sin(half_angle) / angle, 0.5 - angle * angle / 48.0)
    return quat[..., 1:] / ratio.unsqueeze(-1)


def quat_error_magnitude(q1: torch.Tensor, q2: torch.Tensor) -> torch.Tensor:
    """Angle (radians, in ``[0, pi]``) of the rotation between ``q1`` and ``q2``."""
    return axis_angle_from_quat(quat_mul(q1, quat_conjugate(q2))).norm(dim=-1)


def yaw_quat(quat: torch.Tensor) -> torch.Tensor:
    """The rotation about world z only (heading) of ``quat``."""
    _check_last_dim("quat", quat, 4)
    w, x, y, z = quat.unbind(-1)
    yaw = torch.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    zeros = torch.zeros_like(yaw)
    return torch.stack((torch.cos(yaw * 0.5), zeros, zeros, torch.sin(yaw * 0.5)), dim=-1)


def matrix_from_quat(quat: torch.Tensor) -> torch.Tensor:
    """Rotation matrix (..., 3, 3) of a quaternion (normalized on the way)."""
    _check_last_dim("quat", quat, 4)
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
    if matrix.shape[-2:] != (3, 3):
        raise ValueError(f"matrix must have shape (..., 3, 3), got {tuple(matrix.shape)}.")
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
