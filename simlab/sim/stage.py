"""The stage: the ``mujoco.MjSpec`` that spawners add to, under the names Isaac Lab's code uses for its USD stage.

Isaac Lab's code reaches the USD stage (``sim.stage``, ``sim_utils.get_current_stage()``) to look
prims up. In simlab the stage is the MjSpec being built. ``GetPrimAtPath(path).IsValid()`` answers
the one question a spec can: whether an entity (or an ``Xform`` group) was spawned at ``path``. Every
other USD call is an error that says what to use instead, rather than a bare ``AttributeError``.
"""

from __future__ import annotations

import mujoco

_USE_INSTEAD = (
    "Edit the model with the MjSpec API before sim.reset() (spec.body(name), spec.geom(name),"
    " spec.worldbody.add_body(...), spec.delete(element)); spawn with simlab.sim's configs; read poses and"
    " properties from the assets' data (robot.data.body_pos_w, ...) after sim.reset()."
)


class StagePrim:
    """What ``GetPrimAtPath`` returns: a path, valid when something was spawned there."""

    def __init__(self, path: str):
        self._path = path

    def IsValid(self) -> bool:  # noqa: N802 - USD's name
        from simlab.sim.utils import is_prim_path_valid  # utils imports the simulation context

        return is_prim_path_valid(self._path)

    __bool__ = IsValid

    def GetPath(self) -> str:  # noqa: N802 - USD's name
        return self._path

    def GetName(self) -> str:  # noqa: N802 - USD's name
        return self._path.rstrip("/").split("/")[-1]

    def __repr__(self) -> str:
        return f"StagePrim({self._path!r})"

    def __getattr__(self, name: str):
        raise AttributeError(
            f"'{self._path}' names an entity of simlab's MjSpec, not a USD prim: it has no '{name}'"
            f" (IsValid, GetPath and GetName exist). {_USE_INSTEAD}"
        )


class StageSpec(mujoco.MjSpec):
    """The model being built; a ``mujoco.MjSpec`` that knows USD's prim lookup and refuses the rest."""

    def GetPrimAtPath(self, path: str) -> StagePrim:  # noqa: N802 - USD's name
        return StagePrim(str(path))

    def __getattr__(self, name: str):
        if name[:1].isupper():  # USD's Pxr API is CamelCase; MjSpec's is snake_case
            raise AttributeError(
                f"The stage is a mujoco.MjSpec, not a USD stage: it has no '{name}' (GetPrimAtPath(path).IsValid()"
                f" exists). {_USE_INSTEAD}"
            )
        raise AttributeError(f"'mujoco.MjSpec' object has no attribute '{name}'")
