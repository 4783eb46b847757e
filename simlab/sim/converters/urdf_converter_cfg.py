"""Isaac Lab's ``UrdfConverterCfg`` (``isaaclab.sim.converters.urdf_converter_cfg``)."""

from __future__ import annotations

from dataclasses import MISSING
from typing import Literal

from simlab.utils import configclass

from .asset_converter_base_cfg import AssetConverterBaseCfg


@configclass
class UrdfConverterCfg(AssetConverterBaseCfg):
    """A URDF file compiled by MuJoCo's URDF reader into an MJCF file (:class:`UrdfConverter`).

    ``fix_base`` and ``merge_fixed_joints`` (MuJoCo's ``fusestatic``) shape the model. Joint drives
    live in simlab's actuator models (``ArticulationCfg.actuators``), not in the robot file, so
    ``joint_drive`` is accepted and not written; ``self_collision``, ``collider_type``,
    ``collision_from_visuals``, ``replace_cylinders_with_capsules``, ``link_density``,
    ``root_link_name`` and ``convert_mimic_joints_to_normal_joints`` tune Isaac Sim's importer and
    are accepted and ignored (MuJoCo's reader keeps the URDF's collision shapes and masses)."""

    @configclass
    class JointDriveCfg:
        @configclass
        class PDGainsCfg:
            stiffness: dict[str, float] | float = MISSING
            damping: dict[str, float] | float | None = None

        @configclass
        class NaturalFrequencyGainsCfg:
            natural_frequency: dict[str, float] | float = MISSING
            damping_ratio: dict[str, float] | float = 0.005

        drive_type: dict[str, Literal["acceleration", "force"]] | Literal["acceleration", "force"] = "force"
        target_type: dict[str, Literal["none", "position", "velocity"]] | Literal["none", "position", "velocity"] = (
            "position"
        )
        gains: PDGainsCfg | NaturalFrequencyGainsCfg = PDGainsCfg()

    fix_base: bool = MISSING
    """Weld the root link to the world (else it gets a free joint)."""
    root_link_name: str | None = None
    link_density: float = 0.0
    merge_fixed_joints: bool = True
    """Merge links joined by fixed joints into their parent (MuJoCo's ``fusestatic``)."""
    convert_mimic_joints_to_normal_joints: bool = False
    joint_drive: JointDriveCfg | None = JointDriveCfg()
    collision_from_visuals: bool = False
    collider_type: Literal["convex_hull", "convex_decomposition"] = "convex_hull"
    self_collision: bool = False
    replace_cylinders_with_capsules: bool = False
