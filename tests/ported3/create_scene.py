# Isaac Lab 3.0's scripts/tutorials/02_scene/create_scene.py, written out under the 3.0 mapping
# (isaaclab.app -> simlab.app; isaaclab.sim / .assets / .scene -> simlab.v3.*; isaaclab.utils -> simlab.v3.utils;
# isaaclab_assets -> simlab.v3.robots). Nothing else differs: the scene made by instantiate(scene_cfg), reset
# through the _index writers, driven by set_joint_effort_target_index. tests/test_isaaclab3_tutorials.py runs it.

"""Cart-poles in an interactive scene, pushed by random efforts, reset every 500 steps."""

import argparse
from typing import TYPE_CHECKING

from simlab.app import add_launcher_args, launch_simulation

parser = argparse.ArgumentParser(description="Tutorial on using the interactive scene interface.")
parser.add_argument("--num_envs", type=int, default=2, help="Number of environments to spawn.")
add_launcher_args(parser)
args_cli = parser.parse_args()

import torch  # noqa: E402

import simlab.v3.sim as sim_utils  # noqa: E402
from simlab.v3.assets import ArticulationCfg, AssetBaseCfg  # noqa: E402
from simlab.v3.robots import CARTPOLE_CFG  # noqa: E402
from simlab.v3.scene import InteractiveSceneCfg  # noqa: E402
from simlab.v3.sim import SimulationContext  # noqa: E402
from simlab.v3.utils import configclass, instantiate, replace  # noqa: E402

if TYPE_CHECKING:
    from simlab.v3.scene import InteractiveScene


@configclass
class CartpoleSceneCfg(InteractiveSceneCfg):
    ground = AssetBaseCfg(prim_path="/World/defaultGroundPlane", spawn=sim_utils.GroundPlaneCfg())
    dome_light = AssetBaseCfg(
        prim_path="/World/Light", spawn=sim_utils.DomeLightCfg(intensity=3000.0, color=(0.75, 0.75, 0.75))
    )
    cartpole: ArticulationCfg = replace(CARTPOLE_CFG, prim_path="{ENV_REGEX_NS}/Robot")


def run_simulator(sim: sim_utils.SimulationContext, scene: "InteractiveScene"):
    robot = scene["cartpole"]
    sim_dt = sim.get_physics_dt()
    count = 0
    while sim.is_headless_or_exist_active_visualizer():
        if count % 500 == 0:
            count = 0
            # the default pose is in the env's frame: offset it by the env's origin
            root_pose = robot.data.default_root_pose.torch.clone()
            root_pose[:, :3] += scene.env_origins
            robot.write_root_pose_to_sim_index(root_pose=root_pose)
            robot.write_root_velocity_to_sim_index(root_velocity=robot.data.default_root_vel.torch.clone())
            joint_pos = robot.data.default_joint_pos.torch.clone()
            joint_vel = robot.data.default_joint_vel.torch.clone()
            joint_pos += torch.rand_like(joint_pos) * 0.1
            robot.write_joint_position_to_sim_index(position=joint_pos)
            robot.write_joint_velocity_to_sim_index(velocity=joint_vel)
            scene.reset()
            print("[INFO]: Resetting robot state...")
        efforts = torch.randn_like(robot.data.joint_pos.torch) * 5.0
        robot.set_joint_effort_target_index(target=efforts)
        scene.write_data_to_sim()
        sim.step()
        count += 1
        scene.update(sim_dt)


def main():
    sim_cfg = sim_utils.SimulationCfg(device=args_cli.device)
    with launch_simulation(sim_cfg, args_cli):
        sim = SimulationContext(sim_cfg)
        sim.set_camera_view([2.5, 0.0, 4.0], [0.0, 0.0, 2.0])
        scene = instantiate(CartpoleSceneCfg(num_envs=args_cli.num_envs, env_spacing=2.0))
        sim.reset()
        print("[INFO]: Setup complete...")
        run_simulator(sim, scene)


if __name__ == "__main__":
    main()
