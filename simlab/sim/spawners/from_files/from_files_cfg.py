"""Configs of the spawners that read robot files (MJCF, URDF; USD is refused) and of the ground plane."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.utils import configclass

from ...converters.urdf_converter_cfg import UrdfConverterCfg
from ...schemas.schemas_cfg import ArticulationRootPropertiesCfg, FixedTendonPropertiesCfg, JointDrivePropertiesCfg
from ..materials import PreviewSurfaceCfg, RigidBodyMaterialCfg
from ..spawner_cfg import RigidObjectSpawnerCfg, SpawnerCfg
from . import from_files


@configclass
class FileCfg(RigidObjectSpawnerCfg):
    asset_path: str = MISSING
    scale: tuple[float, float, float] | None = None
    articulation_props: ArticulationRootPropertiesCfg | None = None
    joint_drive_props: JointDrivePropertiesCfg | None = None
    fixed_tendons_props: FixedTendonPropertiesCfg | None = None
    visual_material: PreviewSurfaceCfg | None = None


@configclass
class MjcfFileCfg(FileCfg):
    """A robot described in MJCF: one root body under ``<worldbody>``."""

    func: object = from_files.spawn_from_mjcf
    drop_actuators: bool = True


@configclass
class UrdfFileCfg(FileCfg, UrdfConverterCfg):
    """A robot described in URDF, compiled by MuJoCo's URDF reader.

    Takes Isaac Lab's converter settings (it is a ``UrdfConverterCfg`` there too): ``fix_base`` and
    ``merge_fixed_joints`` shape the model; the rest is accepted as :class:`UrdfConverterCfg` says."""

    func: object = from_files.spawn_from_urdf
    fix_base: bool = True
    asset_path: str = MISSING
    joint_drive: UrdfConverterCfg.JointDriveCfg | None = None
    """Accepted and not used: the joints are driven by the ``ArticulationCfg``'s actuators."""


@configclass
class UsdFileCfg(FileCfg):
    """A USD file: a Nucleus path of a robot or prop simlab ships spawns simlab's model of it
    (``usd_stand_ins``); any other path is refused when spawned, saying what to use."""

    func: object = from_files.spawn_from_usd
    usd_path: str = MISSING
    asset_path: str | None = None
    """Unused: a USD file is named by ``usd_path``."""
    variants: object | dict[str, str] | None = None
    """Isaac Lab's USD variant selections; simlab's models have one form each, so only None spawns."""


@configclass
class GroundPlaneCfg(SpawnerCfg):
    func: object = from_files.spawn_ground_plane
    usd_path: str | None = None
    color: tuple[float, float, float] = (0.25, 0.3, 0.35)
    size: tuple[float, float] = (100.0, 100.0)
    physics_material: RigidBodyMaterialCfg = RigidBodyMaterialCfg()
