"""Spawners that read robot files (MJCF, URDF) and the ground plane; Isaac Lab's layout
(``from_files.py``: the spawn functions, ``from_files_cfg.py``: their configs)."""

from .from_files import (
    attach_root_body,
    entity_name,
    has_free_joint,
    spawn_from_mjcf,
    spawn_from_urdf,
    spawn_from_usd,
    spawn_ground_plane,
)
from .from_files_cfg import FileCfg, GroundPlaneCfg, MjcfFileCfg, UrdfFileCfg, UsdFileCfg
