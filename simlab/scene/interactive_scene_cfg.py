"""Configuration of an interactive scene: how many environments and what is in each."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.utils import configclass


@configclass
class InteractiveSceneCfg:
    """Subclass it and declare the scene's entities as fields (asset and sensor configs).

    Entities whose prim path starts with ``{ENV_REGEX_NS}`` exist once per environment; in simlab
    every environment is its own MuJoCo world, so all entities are per environment and environments
    never touch each other.
    """

    num_envs: int = MISSING
    env_spacing: float = MISSING
    """Distance between environment origins on the grid [m]."""
    lazy_sensor_update: bool = True
    replicate_physics: bool = True
    filter_collisions: bool = True
    clone_in_fabric: bool = False
