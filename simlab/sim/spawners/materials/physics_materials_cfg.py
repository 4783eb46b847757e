"""Physics materials: the friction of geoms."""

from __future__ import annotations

from simlab.utils import configclass


@configclass
class RigidBodyMaterialCfg:
    """MuJoCo has one sliding friction per geom: ``static_friction`` sets it."""

    static_friction: float = 0.5
    dynamic_friction: float = 0.5
    restitution: float = 0.0
    friction_combine_mode: str = "average"
    restitution_combine_mode: str = "average"
    compliant_contact_stiffness: float = 0.0
    compliant_contact_damping: float = 0.0

    def friction(self) -> list[float]:
        return [self.static_friction, 0.005, 0.0001]
