"""Spawn a ground plane, a light, cones (visual and rigid) and a cuboid, then step the physics.

The Isaac Lab (2.x) tutorial of the same name with ``isaaclab`` imports replaced by ``simlab`` and
``isaacsim.core.utils.prims`` by ``simlab.sim.utils``; one line differs because MuJoCo cannot do
what it asks: the cuboid has no ``deformable_props`` (simlab's bodies are rigid; with them
``MeshCuboidCfg`` says so). The table's Nucleus USD path spawns simlab's stand-in for it.

    python scripts/tutorials/00_sim/spawn_prims.py --headless --device cpu --max_app_steps 200
"""

import argparse

from simlab.app import AppLauncher

parser = argparse.ArgumentParser(description="Tutorial on spawning prims into the scene.")
AppLauncher.add_app_launcher_args(parser)
args_cli = parser.parse_args()
app_launcher = AppLauncher(args_cli)
simulation_app = app_launcher.app

import simlab.sim as sim_utils  # noqa: E402
import simlab.sim.utils as prim_utils  # noqa: E402
from simlab.utils.assets import ISAAC_NUCLEUS_DIR  # noqa: E402


def design_scene():
    """Designs the scene by spawning ground plane, light, objects and meshes from files."""
    # Ground-plane
    cfg_ground = sim_utils.GroundPlaneCfg()
    cfg_ground.func("/World/defaultGroundPlane", cfg_ground)

    # spawn distant light
    cfg_light_distant = sim_utils.DistantLightCfg(intensity=3000.0, color=(0.75, 0.75, 0.75))
    cfg_light_distant.func("/World/lightDistant", cfg_light_distant, translation=(1, 0, 10))

    # create a new xform prim for all objects to be spawned under
    prim_utils.create_prim("/World/Objects", "Xform")
    # spawn a red cone
    cfg_cone = sim_utils.ConeCfg(
        radius=0.15, height=0.5, visual_material=sim_utils.PreviewSurfaceCfg(diffuse_color=(1.0, 0.0, 0.0))
    )
    cfg_cone.func("/World/Objects/Cone1", cfg_cone, translation=(-1.0, 1.0, 1.0))
    cfg_cone.func("/World/Objects/Cone2", cfg_cone, translation=(-1.0, -1.0, 1.0))

    # spawn a green cone with colliders and rigid body
    cfg_cone_rigid = sim_utils.ConeCfg(
        radius=0.15,
        height=0.5,
        rigid_props=sim_utils.RigidBodyPropertiesCfg(),
        mass_props=sim_utils.MassPropertiesCfg(mass=1.0),
        collision_props=sim_utils.CollisionPropertiesCfg(),
        visual_material=sim_utils.PreviewSurfaceCfg(diffuse_color=(0.0, 1.0, 0.0)),
    )
    cfg_cone_rigid.func(
        "/World/Objects/ConeRigid", cfg_cone_rigid, translation=(-0.2, 0.0, 2.0), orientation=(0.5, 0.0, 0.5, 0.0)
    )

    # spawn a blue cuboid (Isaac Lab makes it deformable: deformable_props=sim_utils.DeformableBodyPropertiesCfg())
    cfg_cuboid = sim_utils.MeshCuboidCfg(
        size=(0.2, 0.5, 0.2),
        rigid_props=sim_utils.RigidBodyPropertiesCfg(),
        mass_props=sim_utils.MassPropertiesCfg(mass=1.0),
        visual_material=sim_utils.PreviewSurfaceCfg(diffuse_color=(0.0, 0.0, 1.0)),
    )
    cfg_cuboid.func("/World/Objects/CuboidDeformable", cfg_cuboid, translation=(0.15, 0.0, 2.0))

    # spawn a usd file of a table into the scene (simlab stands in its 1.05 m high box, docs/porting.md)
    cfg = sim_utils.UsdFileCfg(usd_path=f"{ISAAC_NUCLEUS_DIR}/Props/Mounts/SeattleLabTable/table_instanceable.usd")
    cfg.func("/World/Objects/Table", cfg, translation=(0.0, 0.0, 1.05))


def main():
    """Main function."""
    sim_cfg = sim_utils.SimulationCfg(dt=0.01, device=args_cli.device)
    sim = sim_utils.SimulationContext(sim_cfg)
    sim.set_camera_view([2.0, 0.0, 2.5], [-0.5, 0.0, 0.5])
    design_scene()
    sim.reset()
    print("[INFO]: Setup complete...")
    while simulation_app.is_running():
        sim.step()


if __name__ == "__main__":
    main()
    simulation_app.close()
