"""Configuration of an articulation: its file, initial state and actuator groups."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.actuators import ActuatorBaseCfg
from simlab.utils import configclass

from .articulation import Articulation
from .asset_base import AssetBaseCfg


@configclass
class ArticulationCfg(AssetBaseCfg):
    @configclass
    class InitialStateCfg(AssetBaseCfg.InitialStateCfg):
        lin_vel: tuple[float, float, float] = (0.0, 0.0, 0.0)
        ang_vel: tuple[float, float, float] = (0.0, 0.0, 0.0)
        joint_pos: dict[str, float] = {".*": 0.0}
        """Joint-name patterns to initial positions; every world starts (and resets) there."""
        joint_vel: dict[str, float] = {".*": 0.0}

    class_type: type = Articulation
    init_state: InitialStateCfg = InitialStateCfg()
    soft_joint_pos_limit_factor: float = 1.0
    actuators: dict[str, ActuatorBaseCfg] = MISSING
    articulation_root_prim_path: str | None = None
