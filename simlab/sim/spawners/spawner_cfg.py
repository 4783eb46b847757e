"""Base configuration of everything that adds to the scene's MjSpec."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import MISSING

from simlab.utils import configclass


@configclass
class SpawnerCfg:
    """A spawner's ``func(prim_path, cfg, translation, orientation)`` adds itself to the spec."""

    func: Callable = MISSING
    visible: bool = True
    copy_from_source: bool = True
    """Kept for Isaac Lab compatibility: every world holds its own copy anyway."""


@configclass
class MassPropertiesCfg:
    mass: float | None = None
    density: float | None = None


@configclass
class RigidBodyPropertiesCfg:
    """Only the fields that map onto MuJoCo act; the rest are accepted for compatibility."""

    rigid_body_enabled: bool | None = None
    kinematic_enabled: bool | None = None
    """A kinematic body is a MuJoCo mocap body: it moves only where it is written."""
    disable_gravity: bool | None = None
    linear_damping: float | None = None
    angular_damping: float | None = None
    max_linear_velocity: float | None = None
    max_angular_velocity: float | None = None
    max_depenetration_velocity: float | None = None
    enable_gyroscopic_forces: bool | None = None
    """True (on a robot file's spawner): the scene integrates with MuJoCo's ``implicit`` integrator, which
    takes the gyroscopic term into the step, instead of the default ``implicitfast``."""
    retain_accelerations: bool | None = None
    solver_position_iteration_count: int | None = None
    solver_velocity_iteration_count: int | None = None
    sleep_threshold: float | None = None
    stabilization_threshold: float | None = None


@configclass
class CollisionPropertiesCfg:
    collision_enabled: bool | None = None
    contact_offset: float | None = None
    rest_offset: float | None = None


@configclass
class ArticulationRootPropertiesCfg:
    """Accepted for compatibility; ``fix_root_link`` removes a floating base's free joint."""

    articulation_enabled: bool | None = None
    enabled_self_collisions: bool | None = None
    solver_position_iteration_count: int | None = None
    solver_velocity_iteration_count: int | None = None
    sleep_threshold: float | None = None
    stabilization_threshold: float | None = None
    fix_root_link: bool | None = None


@configclass
class RigidObjectSpawnerCfg(SpawnerCfg):
    """A spawner of bodies that may carry rigid-body, mass and collision properties."""

    mass_props: MassPropertiesCfg | None = None
    rigid_props: RigidBodyPropertiesCfg | None = None
    collision_props: CollisionPropertiesCfg | None = None
    activate_contact_sensors: bool = False
