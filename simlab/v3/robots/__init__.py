"""``isaaclab_assets`` of Isaac Lab 3.0: simlab's robot configs as 3.0 code reads them.

``simlab.v3.robots.<NAME>`` is ``simlab.robots.<NAME>`` written in 3.0's convention: an asset config of
:mod:`simlab.v3.assets` whose ``init_state.rot`` is ``(x, y, z, w)`` (the components reordered once,
here) and whose ``class_type`` carries 3.0's asset API. So 3.0 code that reads a robot's ``rot``, edits
it with :mod:`simlab.v3.utils.math` or builds the robot with ``cfg.class_type(cfg)`` gets 3.0's
convention, while 2.x code importing :mod:`simlab.robots` keeps its ``(w, x, y, z)`` configs. Values that
are not asset configs (joint name lists, actuator configs) are simlab's as they are.

The robot modules too (``isaaclab_assets.robots.<robot>``): ``simlab.v3.robots.<module>`` is
``simlab.robots.<module>`` (``cartpole``, ``ant``, ``franka``, ...) with its configs converted the same
way, made on import for every module of :mod:`simlab.robots` (:class:`_RobotModules`).
"""

from __future__ import annotations

import copy
import dataclasses
import importlib
import importlib.abc
import importlib.machinery
import importlib.util
import sys
import types
from typing import Any

import simlab.assets as _assets2
import simlab.robots as _robots
from simlab.v3 import assets as _assets3

__all__ = ["to_v3"]

# simlab's asset config class -> the class of the same config in Isaac Lab 3.0's convention
_V3_CFG: dict[type, type] = {
    _assets2.AssetBaseCfg: _assets3.AssetBaseCfg,
    _assets2.ArticulationCfg: _assets3.ArticulationCfg,
    _assets2.RigidObjectCfg: _assets3.RigidObjectCfg,
}


def _fields(cfg: Any) -> dict[str, Any]:
    return {f.name: getattr(cfg, f.name) for f in dataclasses.fields(cfg) if f.init}


def to_v3(value: Any) -> Any:
    """``value`` (a config of simlab's asset classes, ``rot`` in (w, x, y, z)) as the config of
    :mod:`simlab.v3.assets` with ``rot`` in (x, y, z, w) and 3.0's asset class; anything else as it is."""
    v3_class = _V3_CFG.get(type(value))
    if v3_class is None:
        return value
    value = copy.deepcopy(value)  # the 3.0 config shares nothing with simlab's, which 2.x code may edit
    values = _fields(value)
    state = _fields(value.init_state)
    w, x, y, z = state["rot"]
    state["rot"] = (x, y, z, w)
    values["init_state"] = v3_class.InitialStateCfg(**state)
    class_type = values.get("class_type")
    if class_type in _assets3.V3_CLASSES:
        values["class_type"] = _assets3.V3_CLASSES[class_type]
    return v3_class(**values)


def __getattr__(name: str) -> Any:
    if name.startswith("_"):
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return to_v3(getattr(_robots, name))


def __dir__() -> list[str]:
    return sorted({*globals(), *dir(_robots)})


class _RobotModules(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds ``simlab.v3.robots.<module>`` for each module of :mod:`simlab.robots`: a module whose names are
    the 2.x module's, asset configs converted by :func:`to_v3` when read."""

    def find_spec(self, fullname: str, path: Any = None, target: Any = None) -> importlib.machinery.ModuleSpec | None:
        parent, _, name = fullname.rpartition(".")
        if parent != __name__ or importlib.util.find_spec(f"{_robots.__name__}.{name}") is None:
            return None
        return importlib.machinery.ModuleSpec(fullname, self)

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType:
        source = importlib.import_module(f"{_robots.__name__}.{spec.name.rpartition('.')[2]}")
        module = types.ModuleType(spec.name, f"``{source.__name__}`` in Isaac Lab 3.0's convention (simlab.v3.robots).")
        module.__getattr__ = lambda name: to_v3(getattr(source, name))
        module.__dir__ = lambda: dir(source)
        public = getattr(source, "__all__", [n for n in vars(source) if not n.startswith("_")])
        module.__all__ = list(public)
        return module

    def exec_module(self, module: types.ModuleType) -> None:
        pass


if not any(isinstance(finder, _RobotModules) for finder in sys.meta_path):
    sys.meta_path.append(_RobotModules())
