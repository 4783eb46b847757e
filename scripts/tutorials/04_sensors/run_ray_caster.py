"""Four balls carrying ray casters drop onto rough ground; each scans a 2 x 2 m grid below it.

Makes the calls of Isaac Lab's (2.x) ``04_sensors/run_ray_caster.py`` under the import mapping: the
ground is Nucleus's ``Environments/Terrains/rough_plane.usd`` (simlab stands in a height field of its own
bumps, docs/porting.md), the balls sit under four ``create_prim`` groups (one world each), the sensor
shares their prim path (``attach_yaw_only=True``, Isaac Lab's older name for ``ray_alignment="yaw"``),
and every step is timed with ``simlab.utils.timer.Timer``. The balls restart from random heights every
250 steps.

    python scripts/tutorials/04_sensors/run_ray_caster.py --headless --device cpu --max_app_steps 300
"""

import argparse

from simlab.app import AppLauncher

parser = argparse.ArgumentParser(description="Ray caster on falling balls.")
AppLauncher.add_app_launcher_args(parser)
args_cli = parser.parse_args()
app_launcher = AppLauncher(args_cli)
simulation_app = app_launcher.app

import torch  # noqa: E402

import simlab.sim as sim_utils  # noqa: E402
import simlab.sim.utils as prim_utils  # noqa: E402
from simlab.assets import RigidObject, RigidObjectCfg  # noqa: E402
from simlab.sensors.ray_caster import RayCaster, RayCasterCfg, patterns  # noqa: E402
from simlab.utils.assets import ISAAC_NUCLEUS_DIR  # noqa: E402
from simlab.utils.timer import Timer  # noqa: E402


def design_scene() -> dict:
    ground = sim_utils.UsdFileCfg(usd_path=f"{ISAAC_NUCLEUS_DIR}/Environments/Terrains/rough_plane.usd")
    ground.func("/World/ground", ground)
    light = sim_utils.DistantLightCfg(intensity=2000)
    light.func("/World/light", light)
    for i, origin in enumerate([[0.25, 0.25, 0.0], [-0.25, 0.25, 0.0], [0.25, -0.25, 0.0], [-0.25, -0.25, 0.0]]):
        prim_utils.create_prim(f"/World/Origin{i}", "Xform", translation=origin)
    balls = RigidObject(
        RigidObjectCfg(
            prim_path="/World/Origin.*/ball",
            spawn=sim_utils.SphereCfg(
                radius=0.25,
                rigid_props=sim_utils.RigidBodyPropertiesCfg(),
                mass_props=sim_utils.MassPropertiesCfg(mass=0.5),
                collision_props=sim_utils.CollisionPropertiesCfg(),
                visual_material=sim_utils.PreviewSurfaceCfg(diffuse_color=(0.0, 0.0, 1.0)),
            ),
        )
    )
    ray_caster = RayCaster(
        cfg=RayCasterCfg(
            prim_path="/World/Origin.*/ball",
            mesh_prim_paths=["/World/ground"],
            pattern_cfg=patterns.GridPatternCfg(resolution=0.1, size=(2.0, 2.0)),
            attach_yaw_only=True,
            debug_vis=not args_cli.headless,
        )
    )
    return {"balls": balls, "ray_caster": ray_caster}


def run_simulator(sim: sim_utils.SimulationContext, entities: dict) -> None:
    ray_caster: RayCaster = entities["ray_caster"]
    balls: RigidObject = entities["balls"]
    start = balls.data.default_root_state.clone()
    start[:, :3] = torch.rand_like(start[:, :3]) * 10  # up to 10 m away and up
    count = 0
    while simulation_app.is_running():
        if count % 250 == 0:
            balls.write_root_pose_to_sim(start[:, :7])
            balls.write_root_velocity_to_sim(start[:, 7:])
            ray_caster.reset()
            count = 0
        sim.step()
        highest = torch.max(ray_caster.data.pos_w).item()
        with Timer(f"Ray-caster update with 4 x {ray_caster.num_rays} rays with max height of {highest:.2f}"):
            ray_caster.update(dt=sim.get_physics_dt(), force_recompute=True)
        count += 1


def main() -> None:
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device=args_cli.device))
    sim.set_camera_view([0.0, 15.0, 15.0], [0.0, 0.0, -2.5])
    entities = design_scene()
    sim.reset()
    print("[INFO]: Setup complete...")
    run_simulator(sim, entities)


if __name__ == "__main__":
    main()
    simulation_app.close()
