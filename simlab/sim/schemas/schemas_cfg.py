"""Isaac Lab's physics schema configs of spawned assets (``isaaclab.sim.schemas.schemas_cfg``): the
fields that map onto MuJoCo act, the rest are accepted so that ported configs load."""

from __future__ import annotations

from simlab.utils import configclass


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
    max_contact_impulse: float | None = None


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
class JointDrivePropertiesCfg:
    """Accepted for compatibility: simlab's joint drives are the actuators of ``ArticulationCfg.actuators``."""

    drive_type: str | None = None
    max_effort: float | None = None
    max_velocity: float | None = None
    stiffness: float | None = None
    damping: float | None = None


@configclass
class FixedTendonPropertiesCfg:
    """Accepted for compatibility: a robot file couples its joints itself (MuJoCo equality constraints or
    tendons, e.g. the Shadow Hand's distal joints)."""

    tendon_enabled: bool | None = None
    stiffness: float | None = None
    damping: float | None = None
    limit_stiffness: float | None = None
    offset: float | None = None
    rest_length: float | None = None
