"""Launch the app with the script's own flags beside the launcher's, and show a cuboid of a given size.

Makes the calls of Isaac Lab's (2.x) ``00_sim/launch_app.py`` under the import mapping (``isaaclab`` ->
``simlab``): script flags ``--size``, ``--width``, ``--height`` next to ``AppLauncher``'s, a ground plane,
a distant light and a white cuboid resting on the ground.

    python scripts/tutorials/00_sim/launch_app.py --size 0.5 --headless --device cpu --max_app_steps 100
"""

import argparse

from simlab.app import AppLauncher

parser = argparse.ArgumentParser(description="Configure the app from the command line.")
parser.add_argument("--size", type=float, default=1.0, help="Edge length of the cuboid [m].")
parser.add_argument("--width", type=int, default=1280, help="Width of the viewport and images.")
parser.add_argument("--height", type=int, default=720, help="Height of the viewport and images.")
AppLauncher.add_app_launcher_args(parser)
args_cli = parser.parse_args()
app_launcher = AppLauncher(args_cli)
simulation_app = app_launcher.app

import simlab.sim as sim_utils  # noqa: E402


def design_scene(size: float) -> None:
    ground = sim_utils.GroundPlaneCfg()
    ground.func("/World/defaultGroundPlane", ground)
    light = sim_utils.DistantLightCfg(intensity=3000.0, color=(0.75, 0.75, 0.75))
    light.func("/World/lightDistant", light, translation=(1, 0, 10))
    cuboid = sim_utils.CuboidCfg(
        size=[size] * 3, visual_material=sim_utils.PreviewSurfaceCfg(diffuse_color=(1.0, 1.0, 1.0))
    )
    cuboid.func("/World/Object", cuboid, translation=(0.0, 0.0, size / 2))  # its base on the ground


def main() -> None:
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.01, device=args_cli.device))
    sim.set_camera_view([2.0, 0.0, 2.5], [-0.5, 0.0, 0.5])
    design_scene(args_cli.size)
    sim.reset()
    print("[INFO]: Setup complete...")
    print(f"[INFO]: Cuboid of {args_cli.size} m, view {args_cli.width} x {args_cli.height}")
    while simulation_app.is_running():
        sim.step()


if __name__ == "__main__":
    main()
    simulation_app.close()
