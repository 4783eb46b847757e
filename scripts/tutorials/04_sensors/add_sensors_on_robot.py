"""ANYmal-C with on-board sensors: a camera on its base, a height scanner and contact sensors on its feet.

Makes the calls of Isaac Lab's (2.x) ``04_sensors/add_sensors_on_robot.py`` under the import mapping:
``CameraCfg`` (RGB and depth at 10 Hz, ROS-convention offset), ``RayCasterCfg`` (a yaw-aligned 1.6 x 1.0 m
grid, its hits drawn with ``debug_vis``), ``ContactSensorCfg`` on ``.*_FOOT`` (history of 6, red/green
markers with ``debug_vis``), and what each reads, printed every step.

    python scripts/tutorials/04_sensors/add_sensors_on_robot.py --enable_cameras --headless --device cpu
"""

import argparse

from simlab.app import AppLauncher

parser = argparse.ArgumentParser(description="Add sensors on a robot.")
parser.add_argument("--num_envs", type=int, default=2, help="Number of environments to spawn.")
AppLauncher.add_app_launcher_args(parser)
args_cli = parser.parse_args()
app_launcher = AppLauncher(args_cli)
simulation_app = app_launcher.app

import torch  # noqa: E402

import simlab.sim as sim_utils  # noqa: E402
from simlab.assets import ArticulationCfg, AssetBaseCfg  # noqa: E402
from simlab.robots.anymal import ANYMAL_C_CFG  # noqa: E402
from simlab.scene import InteractiveScene, InteractiveSceneCfg  # noqa: E402
from simlab.sensors import CameraCfg, ContactSensorCfg, RayCasterCfg, patterns  # noqa: E402
from simlab.utils import configclass  # noqa: E402


@configclass
class SensorsSceneCfg(InteractiveSceneCfg):
    ground = AssetBaseCfg(prim_path="/World/defaultGroundPlane", spawn=sim_utils.GroundPlaneCfg())
    dome_light = AssetBaseCfg(
        prim_path="/World/Light", spawn=sim_utils.DomeLightCfg(intensity=3000.0, color=(0.75, 0.75, 0.75))
    )
    robot: ArticulationCfg = ANYMAL_C_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
    camera = CameraCfg(
        prim_path="{ENV_REGEX_NS}/Robot/base/front_cam",
        update_period=0.1,
        height=480,
        width=640,
        data_types=["rgb", "distance_to_image_plane"],
        spawn=sim_utils.PinholeCameraCfg(
            focal_length=24.0, focus_distance=400.0, horizontal_aperture=20.955, clipping_range=(0.1, 1.0e5)
        ),
        offset=CameraCfg.OffsetCfg(pos=(0.510, 0.0, 0.015), rot=(0.5, -0.5, 0.5, -0.5), convention="ros"),
    )
    height_scanner = RayCasterCfg(
        prim_path="{ENV_REGEX_NS}/Robot/base",
        update_period=0.02,
        offset=RayCasterCfg.OffsetCfg(pos=(0.0, 0.0, 20.0)),
        ray_alignment="yaw",
        pattern_cfg=patterns.GridPatternCfg(resolution=0.1, size=[1.6, 1.0]),
        debug_vis=True,
        mesh_prim_paths=["/World/defaultGroundPlane"],
    )
    contact_forces = ContactSensorCfg(
        prim_path="{ENV_REGEX_NS}/Robot/.*_FOOT", update_period=0.0, history_length=6, debug_vis=True
    )


def reset_robot(scene: InteractiveScene) -> None:
    """Default root pose at each env's origin; default joint angles plus up to 0.1 rad of noise."""
    robot = scene["robot"]
    root = robot.data.default_root_state.clone()
    root[:, :3] += scene.env_origins
    robot.write_root_pose_to_sim(root[:, :7])
    robot.write_root_velocity_to_sim(root[:, 7:])
    joint_pos = robot.data.default_joint_pos.clone() + torch.rand_like(robot.data.default_joint_pos) * 0.1
    robot.write_joint_state_to_sim(joint_pos, robot.data.default_joint_vel.clone())
    scene.reset()
    print("[INFO]: Resetting robot state...")


def run_simulator(sim: sim_utils.SimulationContext, scene: InteractiveScene) -> None:
    dt, count = sim.get_physics_dt(), 0
    while simulation_app.is_running():
        if count % 500 == 0:
            count = 0
            reset_robot(scene)
        scene["robot"].set_joint_position_target(scene["robot"].data.default_joint_pos)  # hold the default pose
        scene.write_data_to_sim()
        sim.step()
        count += 1
        scene.update(dt)

        camera, scanner, contacts = scene["camera"], scene["height_scanner"], scene["contact_forces"]
        print("-------------------------------")
        print(camera)
        print("Received shape of rgb   image: ", camera.data.output["rgb"].shape)
        print("Received shape of depth image: ", camera.data.output["distance_to_image_plane"].shape)
        print("-------------------------------")
        print(scanner)
        print("Received max height value: ", torch.max(scanner.data.ray_hits_w[..., -1]).item())
        print("-------------------------------")
        print(contacts)
        print("Received max contact force of: ", torch.max(contacts.data.net_forces_w).item())


def main() -> None:
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device=args_cli.device))
    sim.set_camera_view(eye=[3.5, 3.5, 3.5], target=[0.0, 0.0, 0.0])
    scene = InteractiveScene(SensorsSceneCfg(num_envs=args_cli.num_envs, env_spacing=2.0))
    sim.reset()
    print("[INFO]: Setup complete...")
    run_simulator(sim, scene)


if __name__ == "__main__":
    main()
    simulation_app.close()
