"""Two ray-cast cameras look at the rough plane from opposite corners; with --save, the first one's images
are written with Replicator's writer and its depth is checked by projecting it to points and back.

Makes the calls of Isaac Lab's (2.x) ``04_sensors/run_ray_caster_camera.py`` under the import mapping:
``RayCasterCameraCfg`` on two ``create_prim`` groups (``/World/Origin_.*/CameraSensor``, one world each)
over Nucleus's ``rough_plane.usd`` (simlab's stand-in height field, docs/porting.md), a 640 x 480 pinhole
pattern at 10 Hz with depth, normals and distance to the camera, the poses set from eye and target,
``omni.replicator.core.BasicWriter`` (``simlab.sensors.replicator``) writing into ``output/ray_caster_camera``
beside this file, and ``unproject_depth`` / ``project_points`` giving back the depth image.

    python scripts/tutorials/04_sensors/run_ray_caster_camera.py --headless --device cpu --save --max_app_steps 12
"""

import argparse

from simlab.app import AppLauncher

parser = argparse.ArgumentParser(description="This script demonstrates how to use the ray-cast camera sensor.")
parser.add_argument("--num_envs", type=int, default=16, help="Number of environments to generate.")
parser.add_argument("--save", action="store_true", default=False, help="Save the obtained data to disk.")
AppLauncher.add_app_launcher_args(parser)
args_cli = parser.parse_args()
app_launcher = AppLauncher(args_cli)
simulation_app = app_launcher.app

import os  # noqa: E402

import torch  # noqa: E402

import simlab.sensors.replicator as rep  # noqa: E402
import simlab.sim as sim_utils  # noqa: E402
import simlab.sim.utils as prim_utils  # noqa: E402
from simlab.sensors.ray_caster import RayCasterCamera, RayCasterCameraCfg, patterns  # noqa: E402
from simlab.utils import convert_dict_to_backend  # noqa: E402
from simlab.utils.assets import ISAAC_NUCLEUS_DIR  # noqa: E402
from simlab.utils.math import project_points, unproject_depth  # noqa: E402


def define_sensor() -> RayCasterCamera:
    # the camera rides on these frames (Xform groups here: one world each)
    prim_utils.create_prim("/World/Origin_00/CameraSensor", "Xform")
    prim_utils.create_prim("/World/Origin_01/CameraSensor", "Xform")
    camera_cfg = RayCasterCameraCfg(
        prim_path="/World/Origin_.*/CameraSensor",
        mesh_prim_paths=["/World/ground"],
        update_period=0.1,
        offset=RayCasterCameraCfg.OffsetCfg(pos=(0.0, 0.0, 0.0), rot=(1.0, 0.0, 0.0, 0.0)),
        data_types=["distance_to_image_plane", "normals", "distance_to_camera"],
        debug_vis=True,
        pattern_cfg=patterns.PinholeCameraPatternCfg(
            focal_length=24.0,
            horizontal_aperture=20.955,
            height=480,
            width=640,
        ),
    )
    return RayCasterCamera(cfg=camera_cfg)


def design_scene() -> dict:
    cfg = sim_utils.UsdFileCfg(usd_path=f"{ISAAC_NUCLEUS_DIR}/Environments/Terrains/rough_plane.usd")
    cfg.func("/World/ground", cfg)
    cfg = sim_utils.DistantLightCfg(intensity=600.0, color=(0.75, 0.75, 0.75))
    cfg.func("/World/Light", cfg)
    return {"camera": define_sensor()}


def run_simulator(sim: sim_utils.SimulationContext, scene_entities: dict) -> None:
    camera: RayCasterCamera = scene_entities["camera"]

    output_dir = os.path.join(os.path.dirname(os.path.realpath(__file__)), "output", "ray_caster_camera")
    rep_writer = rep.BasicWriter(output_dir=output_dir, frame_padding=3)

    # the first camera looks at the origin from (2.5, 2.5, 2.5), the second from the opposite corner
    eyes = torch.tensor([[2.5, 2.5, 2.5], [-2.5, -2.5, 2.5]], device=sim.device)
    targets = torch.tensor([[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]], device=sim.device)
    camera.set_world_poses_from_view(eyes, targets)

    while simulation_app.is_running():
        sim.step()
        camera.update(dt=sim.get_physics_dt())

        print(camera)
        print("Received shape of depth image: ", camera.data.output["distance_to_image_plane"].shape)
        print("-------------------------------")

        if args_cli.save:
            # the first camera's images, as NumPy arrays in Replicator's layout, to its writer
            camera_index = 0
            single_cam_data = convert_dict_to_backend(
                {k: v[camera_index] for k, v in camera.data.output.items()}, backend="numpy"
            )
            single_cam_info = camera.data.info[camera_index]
            rep_output = {"annotators": {}}
            for key, data, info in zip(single_cam_data.keys(), single_cam_data.values(), single_cam_info.values()):
                if info is not None:
                    rep_output["annotators"][key] = {"render_product": {"data": data, **info}}
                else:
                    rep_output["annotators"][key] = {"render_product": {"data": data}}
            rep_output["trigger_outputs"] = {"on_time": camera.frame[camera_index]}
            rep_writer.write(rep_output)

            # depth -> points in the camera frame -> (u, v, depth): the depth comes back
            points_3d_cam = unproject_depth(
                camera.data.output["distance_to_image_plane"], camera.data.intrinsic_matrices
            )
            im_height, im_width = camera.image_shape
            reproj_points = project_points(points_3d_cam, camera.data.intrinsic_matrices)
            reproj_depths = reproj_points[..., -1].view(-1, im_width, im_height).transpose_(1, 2)
            sim_depths = camera.data.output["distance_to_image_plane"].squeeze(-1)
            torch.testing.assert_close(reproj_depths, sim_depths)


def main() -> None:
    sim = sim_utils.SimulationContext()
    sim.set_camera_view([2.5, 2.5, 3.5], [0.0, 0.0, 0.0])
    scene_entities = design_scene()
    sim.reset()
    print("[INFO]: Setup complete...")
    run_simulator(sim=sim, scene_entities=scene_entities)


if __name__ == "__main__":
    main()
    simulation_app.close()
