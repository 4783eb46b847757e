# Isaac Lab 3.0's scripts/tutorials/05_controllers/run_diff_ik.py, written out under the 3.0 mapping
# (docs/porting_3.md: isaaclab.app -> simlab.app; isaaclab.sim / .assets / .scene / .controllers / .markers /
# .utils -> simlab.v3.*; isaaclab.managers -> simlab.managers; isaaclab_assets -> simlab.v3.robots). Nothing
# else differs: goals (x, y, z, qx, qy, qz, qw), the Jacobian from data.body_link_jacobian_w.torch with
# num_base_dofs, poses through .torch and simlab.v3.utils.math. What differs: the table is a box, as in
# simlab's 2.x tutorial (Isaac Sim's stand_instanceable.usd has no stand-in; simlab reads no USD); each reset
# prints how far the hand got from the goal it leaves, so that the test can check the controller reached it.
# tests/test_isaaclab3_tutorials.py runs it.

"""A Franka (or UR10) hand driven through three goal poses by differential IK, a new goal every 150 steps."""

import argparse
from typing import TYPE_CHECKING

from simlab.app import add_launcher_args, launch_simulation

parser = argparse.ArgumentParser(description="Tutorial on using the differential IK controller.")
parser.add_argument("--robot", type=str, default="franka_panda", help="Name of the robot.")
parser.add_argument("--num_envs", type=int, default=128, help="Number of environments to spawn.")
add_launcher_args(parser)
args_cli = parser.parse_args()

import torch  # noqa: E402

import simlab.v3.sim as sim_utils  # noqa: E402
from simlab.managers import SceneEntityCfg  # noqa: E402
from simlab.v3.assets import AssetBaseCfg  # noqa: E402
from simlab.v3.controllers import DifferentialIKController, DifferentialIKControllerCfg  # noqa: E402
from simlab.v3.markers import VisualizationMarkers  # noqa: E402
from simlab.v3.markers.config import FRAME_MARKER_CFG  # noqa: E402
from simlab.v3.robots import FRANKA_PANDA_HIGH_PD_CFG, UR10_CFG  # noqa: E402
from simlab.v3.scene import InteractiveSceneCfg  # noqa: E402
from simlab.v3.utils import clone, configclass, instantiate, replace  # noqa: E402
from simlab.v3.utils.math import quat_error_magnitude, subtract_frame_transforms  # noqa: E402

if TYPE_CHECKING:
    from simlab.v3.scene import InteractiveScene


@configclass
class TableTopSceneCfg(InteractiveSceneCfg):
    ground = AssetBaseCfg(
        prim_path="/World/defaultGroundPlane",
        spawn=sim_utils.GroundPlaneCfg(),
        init_state=AssetBaseCfg.InitialStateCfg(pos=(0.0, 0.0, -1.05)),
    )
    dome_light = AssetBaseCfg(
        prim_path="/World/Light", spawn=sim_utils.DomeLightCfg(intensity=3000.0, color=(0.75, 0.75, 0.75))
    )
    table = AssetBaseCfg(  # 3.0: UsdFileCfg(usd_path=f"{ISAAC_NUCLEUS_DIR}/Props/Mounts/Stand/stand_instanceable.usd")
        prim_path="{ENV_REGEX_NS}/Table",
        spawn=sim_utils.CuboidCfg(size=(1.2, 1.2, 1.0)),
        init_state=AssetBaseCfg.InitialStateCfg(pos=(0.35, 0.0, -0.5)),
    )
    if args_cli.robot == "franka_panda":
        robot = replace(FRANKA_PANDA_HIGH_PD_CFG, prim_path="{ENV_REGEX_NS}/Robot")
    elif args_cli.robot == "ur10":
        robot = replace(UR10_CFG, prim_path="{ENV_REGEX_NS}/Robot")
    else:
        raise ValueError(f"Robot {args_cli.robot} is not supported. Valid: franka_panda, ur10")


def run_simulator(sim: sim_utils.SimulationContext, scene: "InteractiveScene"):
    robot = scene["robot"]
    diff_ik_cfg = DifferentialIKControllerCfg(command_type="pose", use_relative_mode=False, ik_method="dls")
    diff_ik_controller = DifferentialIKController(diff_ik_cfg, num_envs=scene.num_envs, device=sim.device)

    frame_marker_cfg = clone(FRAME_MARKER_CFG)
    frame_marker_cfg.markers["frame"].scale = (0.1, 0.1, 0.1)
    ee_marker = VisualizationMarkers(replace(frame_marker_cfg, prim_path="/Visuals/ee_current"))
    goal_marker = VisualizationMarkers(replace(frame_marker_cfg, prim_path="/Visuals/ee_goal"))

    # goals in the robot's root frame: (x, y, z, qx, qy, qz, qw)
    ee_goals = [
        [0.5, 0.5, 0.7, 0, 0.707, 0, 0.707],
        [0.5, -0.4, 0.6, 0.707, 0, 0, 0.707],
        [0.5, 0, 0.5, 1.0, 0.0, 0.0, 0.0],
    ]
    ee_goals = torch.tensor(ee_goals, device=sim.device)
    current_goal_idx = 0
    ik_commands = torch.zeros(scene.num_envs, diff_ik_controller.action_dim, device=robot.device)
    ik_commands[:] = ee_goals[current_goal_idx]

    if args_cli.robot == "franka_panda":
        robot_entity_cfg = SceneEntityCfg("robot", joint_names=["panda_joint.*"], body_names=["panda_hand"])
    else:
        robot_entity_cfg = SceneEntityCfg("robot", joint_names=[".*"], body_names=["ee_link"])
    robot_entity_cfg.resolve(scene)
    # a fixed base's root body has no Jacobian: the others shift down by one
    ee_jacobi_idx = robot_entity_cfg.body_ids[0] - 1 if robot.is_fixed_base else robot_entity_cfg.body_ids[0]

    sim_dt = sim.get_physics_dt()
    count = 0
    ee_pos_b = ee_quat_b = None
    while sim.is_headless_or_exist_active_visualizer():
        if count % 150 == 0:
            if ee_pos_b is not None:  # (not in 3.0's text) how far the hand is from the goal it is leaving
                pos_error = torch.linalg.norm(ee_pos_b - ik_commands[:, 0:3], dim=-1).max().item()
                rot_error = quat_error_magnitude(ee_quat_b, ik_commands[:, 3:7]).max().item()
                print(f"[INFO]: Goal error: position {pos_error:.4f} m, orientation {rot_error:.4f} rad")
            count = 0
            joint_pos = robot.data.default_joint_pos.torch.clone()
            joint_vel = robot.data.default_joint_vel.torch.clone()
            robot.write_joint_position_to_sim_index(position=joint_pos)
            robot.write_joint_velocity_to_sim_index(velocity=joint_vel)
            robot.reset()
            ik_commands[:] = ee_goals[current_goal_idx]
            joint_pos_des = joint_pos[:, robot_entity_cfg.joint_ids].clone()
            diff_ik_controller.reset()
            diff_ik_controller.set_command(ik_commands)
            current_goal_idx = (current_goal_idx + 1) % len(ee_goals)
        else:
            # the Jacobian's columns: num_base_dofs floating-base ones, then the joints'
            jacobi_joint_ids = [j + robot.num_base_dofs for j in robot_entity_cfg.joint_ids]
            jacobian = robot.data.body_link_jacobian_w.torch[:, ee_jacobi_idx, :, jacobi_joint_ids]
            ee_pose_w = robot.data.body_pose_w.torch[:, robot_entity_cfg.body_ids[0]]
            root_pose_w = robot.data.root_pose_w.torch
            joint_pos = robot.data.joint_pos.torch[:, robot_entity_cfg.joint_ids]
            ee_pos_b, ee_quat_b = subtract_frame_transforms(
                root_pose_w[:, 0:3], root_pose_w[:, 3:7], ee_pose_w[:, 0:3], ee_pose_w[:, 3:7]
            )
            joint_pos_des = diff_ik_controller.compute(ee_pos_b, ee_quat_b, jacobian, joint_pos)

        robot.set_joint_position_target_index(target=joint_pos_des, joint_ids=robot_entity_cfg.joint_ids)
        scene.write_data_to_sim()
        sim.step()
        count += 1
        scene.update(sim_dt)

        ee_pose_w = robot.data.body_state_w.torch[:, robot_entity_cfg.body_ids[0], 0:7]
        ee_marker.visualize(ee_pose_w[:, 0:3], ee_pose_w[:, 3:7])
        goal_marker.visualize(ik_commands[:, 0:3] + scene.env_origins, ik_commands[:, 3:7])


def main():
    sim_cfg = sim_utils.SimulationCfg(dt=0.01, device=args_cli.device)
    with launch_simulation(sim_cfg, args_cli):
        sim = sim_utils.SimulationContext(sim_cfg)
        sim.set_camera_view([2.5, 2.5, 2.5], [0.0, 0.0, 0.0])
        scene = instantiate(TableTopSceneCfg(num_envs=args_cli.num_envs, env_spacing=2.0))
        sim.reset()
        print("[INFO]: Setup complete...")
        run_simulator(sim, scene)


if __name__ == "__main__":
    main()
