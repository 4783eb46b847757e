"""The cube of Isaac Lab's in-hand tasks (its DexCube prop, a USD asset there) as a simlab shape.

Isaac Lab spawns ``Props/Blocks/DexCube/dex_cube_instanceable.usd``, a 6 cm cube, scaled (1.2 for the
Allegro hand) with a density (400 kg/m^3 for the Allegro hand, 567 for the Shadow hand). simlab's
stand-in is a box of the same size and density on a free joint (the one a ported config's
``UsdFileCfg`` naming the DexCube also gets); :func:`dex_cube_cfg` builds its spawner and
:func:`dex_cube_marker_cfg` the goal marker of the same size.
"""

from __future__ import annotations

import simlab.sim as sim_utils
from simlab.sim.spawners.from_files.usd_stand_ins import DEX_CUBE_SIZE

__all__ = ["DEX_CUBE_SIZE", "dex_cube_cfg", "dex_cube_marker_cfg"]


def dex_cube_cfg(scale: float = 1.0, density: float = 400.0) -> sim_utils.CuboidCfg:
    """A dynamic DexCube of edge ``DEX_CUBE_SIZE * scale`` and ``density`` [kg/m^3], Isaac Lab's rigid
    body settings, friction 1 (the tasks' material)."""
    edge = DEX_CUBE_SIZE * scale
    return sim_utils.CuboidCfg(
        size=(edge, edge, edge),
        rigid_props=sim_utils.RigidBodyPropertiesCfg(
            kinematic_enabled=False,
            disable_gravity=False,
            enable_gyroscopic_forces=True,
            solver_position_iteration_count=8,
            solver_velocity_iteration_count=0,
            sleep_threshold=0.005,
            stabilization_threshold=0.0025,
            max_depenetration_velocity=1000.0,
        ),
        mass_props=sim_utils.MassPropertiesCfg(density=density),
        physics_material=sim_utils.RigidBodyMaterialCfg(static_friction=1.0, dynamic_friction=1.0),
        visual_material=sim_utils.PreviewSurfaceCfg(diffuse_color=(0.8, 0.3, 0.2)),
    )


def dex_cube_marker_cfg(scale: float = 1.0) -> sim_utils.CuboidCfg:
    """The goal marker: a DexCube of the same size that is only drawn."""
    edge = DEX_CUBE_SIZE * scale
    return sim_utils.CuboidCfg(
        size=(edge, edge, edge), visual_material=sim_utils.PreviewSurfaceCfg(diffuse_color=(0.2, 0.7, 0.3))
    )
