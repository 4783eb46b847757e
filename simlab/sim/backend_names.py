"""Isaac Lab 3.0's physics backend names (``physics=``, ``presets=``) and the MuJoCo engine each is here."""

from __future__ import annotations

from simlab.utils.errors import ConfigError

__all__ = ["FOREIGN_PHYSICS", "PHYSICS", "engine_for"]

PHYSICS = {  # 3.0's name -> SimulationCfg.engine
    "mujoco": "mujoco",
    "mujoco_warp": "mujoco_warp",
    "mjwarp": "mujoco_warp",
    "newton_mjwarp": "mujoco_warp",
}
FOREIGN_PHYSICS = (
    "physx",
    "isaacsim_physx",
    "ovphysx",
    "newton",
    "newton_xpbd",
    "newton_featherstone",
    "newton_kamino",
)
PHYSICS_ADVICE = (
    "simlab simulates with MuJoCo: use physics=mujoco (MuJoCo C on the CPU) or physics=newton_mjwarp "
    "(MuJoCo Warp, on the GPU)"
)


def engine_for(name: str) -> str:
    """``SimulationCfg.engine`` for Isaac Lab 3.0's physics backend ``name``; others are a ConfigError."""
    if name not in PHYSICS:
        raise ConfigError(f"physics={name}: {PHYSICS_ADVICE}.")
    return PHYSICS[name]
