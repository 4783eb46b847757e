"""The frame transformer on ANYmal-C: every body's frame relative to the base, and a user frame at the foot.

Makes the calls of Isaac Lab's (2.x) ``04_sensors/run_frame_transformer.py`` under the import mapping
(``isaacsim.util.debug_draw._debug_draw`` -> ``simlab.markers.debug_draw``): a ``FrameTransformer`` made
outside a scene (source ``/World/Robot/base``, targets ``/World/Robot/.*`` and ``LF_SHANK`` with an offset
to the foot, named ``LF_FOOT_USER``), ``AppLauncher(headless=...)`` (so ``--max_app_steps`` does not
reach it: bound it with ``SIMLAB_MAX_APP_STEPS``). With a viewer, every 50 steps the next target frame is
drawn with the source frame and a yellow line between them.

    SIMLAB_MAX_APP_STEPS=200 python scripts/tutorials/04_sensors/run_frame_transformer.py --device cpu
"""

import argparse

from simlab.app import AppLauncher

parser = argparse.ArgumentParser(description="Check the FrameTransformer sensor by drawing its frames.")
AppLauncher.add_app_launcher_args(parser)
args_cli = parser.parse_args()
app_launcher = AppLauncher(headless=args_cli.headless)
simulation_app = app_launcher.app

import math  # noqa: E402

import torch  # noqa: E402

import simlab.markers.debug_draw as omni_debug_draw  # noqa: E402
import simlab.sim as sim_utils  # noqa: E402
import simlab.utils.math as math_utils  # noqa: E402
from simlab.assets import Articulation  # noqa: E402
from simlab.markers import VisualizationMarkers  # noqa: E402
from simlab.markers.config import FRAME_MARKER_CFG  # noqa: E402
from simlab.robots.anymal import ANYMAL_C_CFG  # noqa: E402
from simlab.sensors import FrameTransformer, FrameTransformerCfg, OffsetCfg  # noqa: E402


def define_sensor() -> FrameTransformer:
    # the foot, from the shank: 90 degrees about z, then the offset in the rotated frame
    rot_offset = math_utils.quat_from_euler_xyz(torch.zeros(1), torch.zeros(1), torch.tensor(-math.pi / 2))
    pos_offset = math_utils.quat_apply(rot_offset, torch.tensor([0.08795, 0.01305, -0.33797]))
    cfg = FrameTransformerCfg(
        prim_path="/World/Robot/base",
        target_frames=[
            FrameTransformerCfg.FrameCfg(prim_path="/World/Robot/.*"),
            FrameTransformerCfg.FrameCfg(
                prim_path="/World/Robot/LF_SHANK",
                name="LF_FOOT_USER",
                offset=OffsetCfg(pos=tuple(pos_offset.tolist()), rot=tuple(rot_offset[0].tolist())),
            ),
        ],
        debug_vis=False,
    )
    return FrameTransformer(cfg)


def design_scene() -> dict:
    ground = sim_utils.GroundPlaneCfg()
    ground.func("/World/defaultGroundPlane", ground)
    light = sim_utils.DistantLightCfg(intensity=3000.0, color=(0.75, 0.75, 0.75))
    light.func("/World/Light", light)
    robot = Articulation(ANYMAL_C_CFG.replace(prim_path="/World/Robot"))
    return {"robot": robot, "frame_transformer": define_sensor()}


def run_simulator(sim: sim_utils.SimulationContext, entities: dict) -> None:
    robot: Articulation = entities["robot"]
    frames: FrameTransformer = entities["frame_transformer"]
    dt, count, shown = sim.get_physics_dt(), 0, 0
    if not args_cli.headless:  # one frame at a time, with a line from the source to it
        marker_cfg = FRAME_MARKER_CFG.replace(prim_path="/Visuals/FrameVisualizerFromScript")
        marker_cfg.markers["frame"].scale = (0.1, 0.1, 0.1)
        frame_markers = VisualizationMarkers(marker_cfg)
        draw = omni_debug_draw.acquire_debug_draw_interface()
    while simulation_app.is_running():
        robot.set_joint_position_target(robot.data.default_joint_pos.clone())
        robot.write_data_to_sim()
        sim.step()
        count += 1
        robot.update(dt)
        frames.update(dt=dt)
        if args_cli.headless:
            continue
        if count % 50 == 0:
            names = frames.data.target_frame_names
            shown = (shown + 1) % len(names)
            print(f"Displaying Frame ID {shown}: {names[shown]}")
        source_pos, source_quat = frames.data.source_pos_w, frames.data.source_quat_w
        target_pos, target_quat = frames.data.target_pos_w[:, shown], frames.data.target_quat_w[:, shown]
        frame_markers.visualize(torch.cat([source_pos, target_pos]), torch.cat([source_quat, target_quat]))
        draw.clear_lines()
        n = source_pos.shape[0]
        draw.draw_lines(source_pos.tolist(), target_pos.tolist(), [[1.0, 1.0, 0.0, 1.0]] * n, [5.0] * n)


def main() -> None:
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device=args_cli.device))
    sim.set_camera_view(eye=[2.5, 2.5, 2.5], target=[0.0, 0.0, 0.0])
    entities = design_scene()
    sim.reset()
    print("[INFO]: Setup complete...")
    print(f"[INFO]: {len(entities['frame_transformer'].data.target_frame_names)} target frames")
    run_simulator(sim, entities)


if __name__ == "__main__":
    main()
    simulation_app.close()
