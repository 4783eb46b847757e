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
    num_envs_cpu: int | None = None
    """simlab: the env count ``simlab train`` / ``play`` use instead of ``num_envs`` when the simulation
    runs on the CPU and neither ``--num_envs`` nor an ``env.scene.num_envs=`` override sets one (a
    task's CPU default, chosen by ``simlab bench solve``; None: ``num_envs`` on every device)."""
    env_spacing: float = MISSING
    """Distance between environment origins on the grid [m]."""
    lazy_sensor_update: bool = True
    """Either value: simlab updates sensors after every physics step, and in Isaac Lab the two values give
    the same sensor data (lazy updates only postpone the work until the data is read)."""
    replicate_physics: bool = True
    """Only True: every simlab world is a copy of one compiled model (per-env values come from events)."""
    filter_collisions: bool = True
    """Only True: simlab's envs are separate MuJoCo worlds and never collide with each other."""
    clone_in_fabric: bool = False
    """Either value: where Isaac Lab keeps the cloned prims (speed only); simlab has no Fabric stage."""
