"""USD's ``pxr`` (``from pxr import Usd, UsdGeom``) for what Isaac Lab's task files read from the stage: a body's pose.

Isaac Lab's Franka-cabinet env reads the hand's and fingers' poses once, at start-up::

    xformable = UsdGeom.Xformable(stage.GetPrimAtPath("/World/envs/env_0/Robot/panda_link7"))
    transform = xformable.ComputeLocalToWorldTransform(0)  # or Usd.TimeCode.Default()
    transform.ExtractTranslation(), transform.ExtractRotationQuat()  # .real / .imaginary, GetReal() / GetImaginary()

Its USD stage holds the poses the assets were spawned in (physics writes to Fabric, not USD). Here the
prim path names a body of simlab's model in one env (``/World/envs/env_<i>/<asset>/<body>``, or the
asset itself for its root body) and the transform is that body's pose in the initial state, where every
reset starts (the assets' default root poses and joint positions), in the world frame with env ``i``'s
origin: what ``asset.data.body_pos_w`` and ``body_quat_w`` read after a reset. The stage has no time
samples, so every time code gives that pose, as USD's default value. The rest of ``pxr`` (``Sdf``,
``Gf``, ``UsdPhysics``, ``Semantics``, other ``UsdGeom`` schemas) raises an error that says so.
"""

from __future__ import annotations

import math
import re
from typing import Any

import mujoco
import numpy as np

from .simulation_context import SimulationContext

__all__ = ["Usd", "UsdGeom"]

_ENV_BODY = re.compile(r"/World/envs/env_(\d+)/(.+)")
_HAS = "simlab maps Usd.TimeCode and UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(time) only"


def _refusal(name: str) -> str:
    return (
        f"pxr.{name}: simlab's stage is a MuJoCo MjSpec, not USD ({_HAS}, for the bodies' spawn poses). Read poses"
        " from the assets' data (robot.data.body_pos_w, body_quat_w) and edit the model with the MjSpec API."
    )


class _Refusing:
    """Other attributes of USD's types: an error naming what exists."""

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        raise AttributeError(_refusal(f"{type(self).__name__}.{name}"))


class TimeCode(float):
    """``Usd.TimeCode``: a time on the stage; ``Default()`` is USD's default time (NaN)."""

    @classmethod
    def Default(cls) -> TimeCode:  # noqa: N802 - USD's name
        return cls(math.nan)

    def IsDefault(self) -> bool:  # noqa: N802 - USD's name
        return math.isnan(self)

    def GetValue(self) -> float:  # noqa: N802 - USD's name
        return float(self)


class Vec3d(tuple):
    """``Gf.Vec3d``: three floats, indexed."""


class Quatd(_Refusing):
    """``Gf.Quatd``: a rotation as a real part and an imaginary (x, y, z) part."""

    def __init__(self, real: float, imaginary: tuple[float, float, float]):
        self.real, self.imaginary = float(real), Vec3d(float(v) for v in imaginary)

    def GetReal(self) -> float:  # noqa: N802 - USD's name
        return self.real

    def GetImaginary(self) -> Vec3d:  # noqa: N802 - USD's name
        return self.imaginary

    def __repr__(self) -> str:
        return f"Gf.Quatd({self.real}, Gf.Vec3d{tuple(self.imaginary)})"


class Matrix4d(_Refusing):
    """``Gf.Matrix4d`` of a rigid transform, in USD's row-vector layout: rotation transposed in the
    upper 3x3 block, translation in the last row."""

    def __init__(self, translation: np.ndarray, quat_wxyz: np.ndarray):
        self._translation = np.asarray(translation, dtype=np.float64)
        self._quat = np.asarray(quat_wxyz, dtype=np.float64) / np.linalg.norm(quat_wxyz)

    def ExtractTranslation(self) -> Vec3d:  # noqa: N802 - USD's name
        return Vec3d(float(v) for v in self._translation)

    def ExtractRotationQuat(self) -> Quatd:  # noqa: N802 - USD's name
        return Quatd(self._quat[0], self._quat[1:])

    def __getitem__(self, row: int) -> tuple[float, ...]:
        matrix = np.eye(4)
        rotation = np.zeros(9)
        mujoco.mju_quat2Mat(rotation, self._quat)
        matrix[:3, :3], matrix[3, :3] = rotation.reshape(3, 3).T, self._translation
        return tuple(float(v) for v in matrix[row])

    def __repr__(self) -> str:
        return f"Gf.Matrix4d({[self[i] for i in range(4)]})"


class Xformable(_Refusing):
    """``UsdGeom.Xformable(prim)``: the spawn pose of the body that the prim's path names."""

    def __init__(self, prim: Any):
        self._path = str(prim.GetPath() if hasattr(prim, "GetPath") else prim).rstrip("/")

    def GetPath(self) -> str:  # noqa: N802 - USD's name
        return self._path

    def ComputeLocalToWorldTransform(self, time: float | TimeCode = TimeCode.Default()) -> Matrix4d:  # noqa: B008, N802
        """The body's pose in the initial state, env origin included (any ``time``: no time samples)."""
        return Matrix4d(*_initial_body_pose(self._path))


def _initial_body_pose(path: str) -> tuple[np.ndarray, np.ndarray]:
    """(world position, (w, x, y, z) quaternion) of the body ``path`` names, in the worlds' initial state."""
    where = f"UsdGeom.Xformable('{path}').ComputeLocalToWorldTransform()"
    sim = SimulationContext.instance()
    if sim is None or sim.model is None:
        raise RuntimeError(f"{where}: the bodies have poses once the simulation is built (after sim.reset()).")
    match = _ENV_BODY.fullmatch(path)
    if match is None:
        raise ValueError(
            f"{where}: simlab's stage has the poses of each env's bodies, '/World/envs/env_<i>/<asset>/<body>'."
        )
    env, name = int(match[1]), match[2]
    if env >= sim.num_envs:
        raise ValueError(f"{where}: there are {sim.num_envs} envs (env_0 to env_{sim.num_envs - 1}).")
    model = sim.model
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name)
    if body < 0:  # the asset's own prim: its root body (the one of its bodies that hangs from the world)
        roots = [
            b
            for b in range(1, model.nbody)
            if model.body_parentid[b] == 0 and model.body(b).name.startswith(f"{name}/")
        ]
        if len(roots) != 1:
            asset = name.split("/")[0]
            names = [model.body(b).name for b in range(1, model.nbody) if model.body(b).name.startswith(f"{asset}/")]
            known = ", ".join(f"'{n}'" for n in names[:8]) or "none"
            raise ValueError(f"{where}: no body '{name}' in the model (bodies of '{asset}': {known}).")
        body = roots[0]
    data = mujoco.MjData(model)
    data.qpos[:] = sim.backend.initial_qpos.cpu().numpy()
    mujoco.mj_kinematics(model, data)
    origin = np.asarray(sim.env_origins[env].tolist(), dtype=np.float64)
    return data.xpos[body] + origin, data.xquat[body].copy()


Usd = type("Usd", (_Refusing,), {"TimeCode": TimeCode})()
UsdGeom = type("UsdGeom", (_Refusing,), {"Xformable": Xformable})()


def __getattr__(name: str) -> Any:
    if name.startswith("__"):  # the import machinery's probes (__path__, ...)
        raise AttributeError(name)
    raise ImportError(_refusal(name))
