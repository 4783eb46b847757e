"""``isaaclab_assets.robots.<robot>`` of Isaac Lab 3.0 (issue 42): ``simlab.v3.robots.<module>`` is each module
of simlab.robots with its robot configs in 3.0's convention; simlab.robots.<module> stays 2.x's."""

from __future__ import annotations

import importlib
import pkgutil

import pytest

import simlab.assets as assets2
import simlab.robots
import simlab.v3.assets as assets3


def test_every_robot_module_has_a_3_0_twin_with_its_configs_converted():
    modules = [m.name for m in pkgutil.iter_modules(simlab.robots.__path__) if not m.name.startswith("_")]
    assert {"ant", "cartpole", "franka", "anymal", "unitree"} <= set(modules)
    for name in modules:
        module2 = importlib.import_module(f"simlab.robots.{name}")
        module3 = importlib.import_module(f"simlab.v3.robots.{name}")
        for attr in dir(module2):
            value2 = getattr(module2, attr)
            if type(value2) not in (assets2.ArticulationCfg, assets2.RigidObjectCfg):
                continue
            value3 = getattr(module3, attr)
            assert isinstance(value3, (assets3.ArticulationCfg, assets3.RigidObjectCfg)), f"{name}.{attr}"
            w, x, y, z = value2.init_state.rot
            assert value3.init_state.rot == (x, y, z, w), f"{name}.{attr}"
            assert value3.spawn == value2.spawn


def test_3_0_imports_of_a_robot_module_read_3_0_order_and_2_x_imports_keep_theirs():
    from simlab.v3.robots.cartpole import CARTPOLE_CFG as CARTPOLE_3

    from simlab.robots.cartpole import CARTPOLE_CFG as CARTPOLE_2

    assert CARTPOLE_2.init_state.rot == (1.0, 0.0, 0.0, 0.0) and CARTPOLE_3.init_state.rot == (0.0, 0.0, 0.0, 1.0)
    assert type(CARTPOLE_2) is assets2.ArticulationCfg and CARTPOLE_3.class_type is assets3.Articulation
    namespace: dict = {}
    exec("from simlab.v3.robots.ant import *", namespace)  # noqa: S102 - 3.0 code's star import
    assert namespace["ANT_CFG"].init_state.rot == (0.0, 0.0, 0.0, 1.0)
    with pytest.raises(ModuleNotFoundError, match="simlab.v3.robots.nothing"):
        importlib.import_module("simlab.v3.robots.nothing")
