"""Base configuration of everything that adds to the scene's MjSpec."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import MISSING

from simlab.sim.schemas.schemas_cfg import (
    CollisionPropertiesCfg,
    MassPropertiesCfg,
    RigidBodyPropertiesCfg,
)
from simlab.utils import configclass


@configclass
class SpawnerCfg:
    """A spawner's ``func(prim_path, cfg, translation, orientation)`` adds itself to the spec."""

    func: Callable = MISSING
    visible: bool = True
    copy_from_source: bool = True
    """Kept for Isaac Lab compatibility: every world holds its own copy anyway."""
    semantic_tags: list[tuple[str, str]] | None = None
    """Isaac Lab's semantic labels ``[("class", "robot"), ...]`` for Replicator's segmentation; kept so
    that configs setting them load: simlab's cameras render RGB and depth, and nothing reads them."""


@configclass
class RigidObjectSpawnerCfg(SpawnerCfg):
    """A spawner of bodies that may carry rigid-body, mass and collision properties."""

    mass_props: MassPropertiesCfg | None = None
    rigid_props: RigidBodyPropertiesCfg | None = None
    collision_props: CollisionPropertiesCfg | None = None
    activate_contact_sensors: bool = False
