"""``isaaclab.utils.math`` of Isaac Lab 3.0: simlab's math with quaternions in (x, y, z, w) order.

Each function here takes and returns quaternions as Isaac Lab 3.0 does, ``(x, y, z, w)``, and calls
:mod:`simlab.utils.math` (``(w, x, y, z)``, Isaac Lab 2.x's order and MuJoCo's) in between. Which
arguments and results are quaternions is written down per function in :data:`QUATERNION_ARGS`; a
function of :mod:`simlab.utils.math` that handles quaternions but is not listed there is not offered
here (``AttributeError`` saying so), so nothing reaches a 2.x function in the wrong order. The
functions without quaternions are simlab's own.
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable
from typing import Any

import torch

import simlab.utils.math as _math
from simlab.v3._proxy import as_v3

__all__ = ["QUATERNION_ARGS", "wxyz_from_xyzw", "xyzw_from_wxyz"]


def xyzw_from_wxyz(quat: torch.Tensor) -> torch.Tensor:
    """A (..., 4) quaternion in (w, x, y, z) order, written in (x, y, z, w) order."""
    return torch.roll(quat, -1, dims=-1)


def wxyz_from_xyzw(quat: torch.Tensor) -> torch.Tensor:
    """A (..., 4) quaternion in (x, y, z, w) order, written in (w, x, y, z) order."""
    return torch.roll(quat, 1, dims=-1)


# name -> (its quaternion arguments, which results are quaternions: True (the result), False (none),
# or one flag per element of a returned tuple)
QUATERNION_ARGS: dict[str, tuple[tuple[str, ...], bool | tuple[bool, ...]]] = {
    "quat_mul": (("q1", "q2"), True),
    "quat_conjugate": (("q",), True),
    "quat_inv": (("q",), True),
    "quat_unique": (("q",), True),
    "quat_apply": (("quat",), False),
    "quat_apply_inverse": (("quat",), False),
    "quat_rotate": (("quat",), False),
    "quat_rotate_inverse": (("quat",), False),
    "quat_apply_yaw": (("quat",), False),
    "quat_from_euler_xyz": ((), True),
    "euler_xyz_from_quat": (("quat",), False),
    "quat_from_angle_axis": ((), True),
    "axis_angle_from_quat": (("quat",), False),
    "quat_error_magnitude": (("q1", "q2"), False),
    "quat_box_minus": (("q1", "q2"), False),
    "quat_box_plus": (("q",), True),
    "quat_slerp": (("q1", "q2"), True),
    "yaw_quat": (("quat",), True),
    "matrix_from_quat": (("quaternions",), False),
    "quat_from_matrix": ((), True),
    "combine_frame_transforms": (("q01", "q12"), (False, True)),
    "subtract_frame_transforms": (("q01", "q02"), (False, True)),
    "compute_pose_error": (("q01", "q02"), (False, False)),  # rot_error_type="quat": see below
    "apply_delta_pose": (("source_rot",), (False, True)),
    "rigid_body_twist_transform": (("q01",), (False, False)),
    "is_identity_pose": (("rot",), False),
    "transform_points": (("quat",), False),
    "default_orientation": ((), True),
    "random_orientation": ((), True),
    "random_yaw_orientation": ((), True),
    "convert_camera_frame_orientation_convention": (("orientation",), True),
}

# names Isaac Lab 3.0 removed, with what to do instead
REMOVED = {
    "convert_quat": "Isaac Lab 3.0 removed convert_quat: its quaternions are (x, y, z, w) everywhere, so drop the "
    "conversion (simlab.v3.utils.math.wxyz_from_xyzw / xyzw_from_wxyz convert explicitly)",
}


def _as_xyzw(result: Any, flags: bool | tuple[bool, ...]) -> Any:
    if isinstance(flags, tuple):
        return tuple(xyzw_from_wxyz(r) if f and r is not None else r for r, f in zip(result, flags))
    return xyzw_from_wxyz(result) if flags else result


def _in_xyzw(name: str, fn: Callable, args: tuple[str, ...], out: bool | tuple[bool, ...]) -> Callable:
    signature = inspect.signature(fn)

    @functools.wraps(fn)
    def wrapper(*a: Any, **kw: Any) -> Any:
        bound = signature.bind(*a, **kw)
        for arg in args:
            value = bound.arguments.get(arg)
            if value is not None:  # an asset data field without .torch is read as 3.0 reads it
                bound.arguments[arg] = wxyz_from_xyzw(torch.as_tensor(as_v3(value)))
        flags = out
        if name == "compute_pose_error" and bound.arguments.get("rot_error_type") == "quat":
            flags = (False, True)
        return _as_xyzw(fn(*bound.args, **bound.kwargs), flags)

    wrapper.__doc__ = f"{fn.__doc__ or ''}\n\nQuaternions in (x, y, z, w) order (Isaac Lab 3.0's)."
    return wrapper


WITHOUT_QUATERNIONS = ("make_pose",)  # its ``rot`` is a rotation matrix


def _handles_quaternions(name: str, fn: Any) -> bool:
    if name in WITHOUT_QUATERNIONS:
        return False
    if "quat" in name or "orientation" in name:
        return True
    try:
        params = inspect.signature(fn).parameters
    except (TypeError, ValueError):
        return False
    return any("quat" in p or p in ("q", "q1", "q2", "q01", "q02", "q12", "rot") for p in params)


_WRAPPED = {name: _in_xyzw(name, getattr(_math, name), *spec) for name, spec in QUATERNION_ARGS.items()}
globals().update(_WRAPPED)
__all__ += sorted(_WRAPPED)


def __getattr__(name: str) -> Any:
    if name in REMOVED:
        raise AttributeError(f"simlab.v3.utils.math.{name}: {REMOVED[name]}.")
    fn = getattr(_math, name, None)
    if fn is None or name.startswith("_"):
        raise AttributeError(f"module 'simlab.v3.utils.math' has no attribute '{name}'")
    if callable(fn) and _handles_quaternions(name, fn):
        raise AttributeError(
            f"simlab.v3.utils.math.{name} is not offered in (x, y, z, w) order yet; call "
            f"simlab.utils.math.{name} with (w, x, y, z) quaternions (wxyz_from_xyzw / xyzw_from_wxyz convert)."
        )
    return fn
