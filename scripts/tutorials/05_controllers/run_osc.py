"""Press the Franka's fingertip against a tilted wall with the operational-space controller.

Isaac Lab's ``05_controllers/run_osc.py`` tutorial with ``isaaclab`` imports replaced by ``simlab``.
The hand tracks poses on a wall tilted 45 degrees (motion control along the wall's plane and in
orientation) while pushing into it with 10 N (force control along the wall's normal, closed-loop on
the wall's contact sensor); every 500 steps the arm is reset and the next goal (position and
stiffness) is taken. After each reset and every 100 steps the script prints the remaining error of
the motion-controlled axes and the size of the measured contact force.

    python scripts/tutorials/05_controllers/run_osc.py --num_envs 4 --headless --device cpu
"""

import argparse

from simlab.app import AppLauncher

parser = argparse.ArgumentParser(description="Tutorial on using the operational space controller.")
parser.add_argument("--num_envs", type=int, default=128, help="Number of environments to spawn.")
AppLauncher.add_app_launcher_args(parser)
args_cli = parser.parse_args()

app_launcher = AppLauncher(args_cli)
simulation_app = app_launcher.app

import torch  # noqa: E402

import simlab.sim as sim_utils  # noqa: E402
from simlab.assets import Articulation, AssetBaseCfg  # noqa: E402
from simlab.controllers import OperationalSpaceController, OperationalSpaceControllerCfg  # noqa: E402
from simlab.markers import VisualizationMarkers  # noqa: E402
from simlab.markers.config import FRAME_MARKER_CFG  # noqa: E402
from simlab.robots.franka import FRANKA_PANDA_HIGH_PD_CFG  # noqa: E402
from simlab.scene import InteractiveScene, InteractiveSceneCfg  # noqa: E402
from simlab.sensors import ContactSensorCfg  # noqa: E402
from simlab.utils import configclass  # noqa: E402
from simlab.utils.math import (  # noqa: E402
    combine_frame_transforms,
    matrix_from_quat,
    quat_apply_inverse,
    quat_inv,
    subtract_frame_transforms,
)


@configclass
class SceneCfg(InteractiveSceneCfg):
    """A ground plane, a light, a wall tilted 45 degrees in front of the robot (with a contact sensor)
    and the Franka with its joint drives switched off (the controller commands torques)."""

    ground = AssetBaseCfg(prim_path="/World/defaultGroundPlane", spawn=sim_utils.GroundPlaneCfg())
    dome_light = AssetBaseCfg(
        prim_path="/World/Light", spawn=sim_utils.DomeLightCfg(intensity=3000.0, color=(0.75, 0.75, 0.75))
    )
    tilted_wall = AssetBaseCfg(
        prim_path="{ENV_REGEX_NS}/TiltedWall",
        spawn=sim_utils.CuboidCfg(
            size=(2.0, 1.5, 0.01),
            collision_props=sim_utils.CollisionPropertiesCfg(),
            visual_material=sim_utils.PreviewSurfaceCfg(diffuse_color=(1.0, 0.0, 0.0), opacity=0.1),
            rigid_props=sim_utils.RigidBodyPropertiesCfg(kinematic_enabled=True),
            activate_contact_sensors=True,
        ),
        init_state=AssetBaseCfg.InitialStateCfg(
            pos=(0.6 + 0.085, 0.0, 0.3), rot=(0.9238795325, 0.0, -0.3826834324, 0.0)
        ),
    )
    contact_forces = ContactSensorCfg(
        prim_path="/World/envs/env_.*/TiltedWall", update_period=0.0, history_length=2, debug_vis=False
    )
    robot = FRANKA_PANDA_HIGH_PD_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
    robot.actuators["panda_shoulder"].stiffness = 0.0
    robot.actuators["panda_shoulder"].damping = 0.0
    robot.actuators["panda_forearm"].stiffness = 0.0
    robot.actuators["panda_forearm"].damping = 0.0
    robot.spawn.rigid_props.disable_gravity = True


def run_simulator(sim: sim_utils.SimulationContext, scene: InteractiveScene):
    robot = scene["robot"]
    contact_forces = scene["contact_forces"]
    ee_frame_idx = robot.find_bodies("panda_leftfinger")[0][0]
    arm_joint_ids = robot.find_joints(["panda_joint.*"])[0]

    # pose along the wall's plane and in orientation, 10 N into the wall along its normal
    osc_cfg = OperationalSpaceControllerCfg(
        target_types=["pose_abs", "wrench_abs"],
        impedance_mode="variable_kp",
        inertial_dynamics_decoupling=True,
        partial_inertial_dynamics_decoupling=False,
        gravity_compensation=False,
        motion_damping_ratio_task=1.0,
        contact_wrench_stiffness_task=[0.0, 0.0, 0.1, 0.0, 0.0, 0.0],
        motion_control_axes_task=[1, 1, 0, 1, 1, 1],
        contact_wrench_control_axes_task=[0, 0, 1, 0, 0, 0],
        nullspace_control="position",
    )
    osc = OperationalSpaceController(osc_cfg, num_envs=scene.num_envs, device=sim.device)

    frame_marker_cfg = FRAME_MARKER_CFG.copy()
    frame_marker_cfg.markers["frame"].scale = (0.1, 0.1, 0.1)
    ee_marker = VisualizationMarkers(frame_marker_cfg.replace(prim_path="/Visuals/ee_current"))
    goal_marker = VisualizationMarkers(frame_marker_cfg.replace(prim_path="/Visuals/ee_goal"))

    # goals in the robot's root frame: pose (x, y, z, qw, qx, qy, qz), the hand turned over and
    # tilted to face the wall, the wrench in the goal's own frame, the motion stiffness of each axis
    ee_goal_pose_set_tilted_b = torch.tensor(
        [
            [0.6, 0.15, 0.3, 0.0, 0.92387953, 0.0, 0.38268343],
            [0.6, -0.3, 0.3, 0.0, 0.92387953, 0.0, 0.38268343],
            [0.8, 0.0, 0.5, 0.0, 0.92387953, 0.0, 0.38268343],
        ],
        device=sim.device,
    )
    ee_goal_wrench_set_tilted_task = torch.tensor([[0.0, 0.0, 10.0, 0.0, 0.0, 0.0]] * 3, device=sim.device)
    kp_set_task = torch.tensor(
        [[360.0] * 6, [420.0] * 6, [320.0] * 6],
        device=sim.device,
    )
    ee_target_set = torch.cat([ee_goal_pose_set_tilted_b, ee_goal_wrench_set_tilted_task, kp_set_task], dim=-1)

    sim_dt = sim.get_physics_dt()
    robot.update(dt=sim_dt)
    joint_centers = torch.mean(robot.data.soft_joint_pos_limits[:, arm_joint_ids, :], dim=-1)
    jacobian_b, mass_matrix, gravity, ee_pose_b, ee_vel_b, root_pose_w, ee_pose_w, ee_force_b, joint_pos, joint_vel = (
        update_states(sim, scene, robot, ee_frame_idx, arm_joint_ids, contact_forces)
    )

    current_goal_idx = 0
    ee_target_pose_b = torch.zeros(scene.num_envs, 7, device=sim.device)
    ee_target_pose_w = torch.zeros(scene.num_envs, 7, device=sim.device)
    zero_joint_efforts = torch.zeros(scene.num_envs, robot.num_joints, device=sim.device)

    count = 0
    while simulation_app.is_running():
        if count % 500 == 0:
            # back to the default posture, zero torques, the next goal
            robot.write_joint_state_to_sim(robot.data.default_joint_pos.clone(), robot.data.default_joint_vel.clone())
            robot.set_joint_effort_target(zero_joint_efforts)
            robot.write_data_to_sim()
            robot.reset()
            contact_forces.reset()
            robot.update(sim_dt)
            _, _, _, ee_pose_b, _, _, _, _, _, _ = update_states(
                sim, scene, robot, ee_frame_idx, arm_joint_ids, contact_forces
            )
            command, ee_target_pose_b, ee_target_pose_w, current_goal_idx = update_target(
                sim, scene, osc, root_pose_w, ee_target_set, current_goal_idx
            )
            osc.reset()
            command, task_frame_pose_b = convert_to_task_frame(osc, command=command, ee_target_pose_b=ee_target_pose_b)
            osc.set_command(command=command, current_ee_pose_b=ee_pose_b, current_task_frame_pose_b=task_frame_pose_b)
        else:
            (
                jacobian_b,
                mass_matrix,
                gravity,
                ee_pose_b,
                ee_vel_b,
                root_pose_w,
                ee_pose_w,
                ee_force_b,
                joint_pos,
                joint_vel,
            ) = update_states(sim, scene, robot, ee_frame_idx, arm_joint_ids, contact_forces)
            joint_efforts = osc.compute(
                jacobian_b=jacobian_b,
                current_ee_pose_b=ee_pose_b,
                current_ee_vel_b=ee_vel_b,
                current_ee_force_b=ee_force_b,
                mass_matrix=mass_matrix,
                gravity=gravity,
                current_joint_pos=joint_pos,
                current_joint_vel=joint_vel,
                nullspace_joint_pos_target=joint_centers,
            )
            robot.set_joint_effort_target(joint_efforts, joint_ids=arm_joint_ids)
            robot.write_data_to_sim()
            if count % 100 == 0 or count % 500 == 1:  # right after each reset and every 100 steps
                print_tracking(osc, ee_force_b, count)

        ee_marker.visualize(ee_pose_w[:, 0:3], ee_pose_w[:, 3:7])
        goal_marker.visualize(ee_target_pose_w[:, 0:3], ee_target_pose_w[:, 3:7])
        sim.step()
        robot.update(sim_dt)
        scene.update(sim_dt)
        count += 1


def print_tracking(osc: OperationalSpaceController, ee_force_b: torch.Tensor, count: int):
    """The largest remaining error over the envs on the motion-controlled axes (the pose error the
    controller saw last, rotated into the task frame), and the mean size of the measured contact force."""
    rot = matrix_from_quat(osc.task_frame_pose_b[:, 3:])
    error_task = torch.cat(
        [
            (rot.transpose(-1, -2) @ osc.pose_error_b[:, :3, None])[..., 0],
            (rot.transpose(-1, -2) @ osc.pose_error_b[:, 3:, None])[..., 0],
        ],
        dim=-1,
    )
    axes = torch.tensor(osc.cfg.motion_control_axes_task, dtype=torch.bool, device=error_task.device)
    position_error = error_task[:, :3][:, axes[:3]].norm(dim=-1).max()
    orientation_error = error_task[:, 3:][:, axes[3:]].norm(dim=-1).max()
    print(
        f"[INFO]: step {count}: position error {position_error:.4f} m, orientation error {orientation_error:.4f} rad,"
        f" contact force {ee_force_b.norm(dim=-1).mean():.2f} N"
    )


def update_states(
    sim: sim_utils.SimulationContext,
    scene: InteractiveScene,
    robot: Articulation,
    ee_frame_idx: int,
    arm_joint_ids: list[int],
    contact_forces,
):
    """The controller's inputs: the end effector's Jacobian, pose and velocity in the root frame, the
    arm's mass matrix and gravity torques, the contact force and the joint states."""
    # a fixed base is left out of the Jacobians: body i is row i - 1
    ee_jacobi_idx = ee_frame_idx - 1
    jacobian_w = robot.root_physx_view.get_jacobians()[:, ee_jacobi_idx, :, arm_joint_ids]
    mass_matrix = robot.root_physx_view.get_generalized_mass_matrices()[:, arm_joint_ids, :][:, :, arm_joint_ids]
    gravity = robot.root_physx_view.get_gravity_compensation_forces()[:, arm_joint_ids]
    # the Jacobian from the world to the root frame
    jacobian_b = jacobian_w.clone()
    root_rot_matrix = matrix_from_quat(quat_inv(robot.data.root_quat_w))
    jacobian_b[:, :3, :] = torch.bmm(root_rot_matrix, jacobian_b[:, :3, :])
    jacobian_b[:, 3:, :] = torch.bmm(root_rot_matrix, jacobian_b[:, 3:, :])

    root_pos_w = robot.data.root_pos_w
    root_quat_w = robot.data.root_quat_w
    ee_pos_w = robot.data.body_pos_w[:, ee_frame_idx]
    ee_quat_w = robot.data.body_quat_w[:, ee_frame_idx]
    ee_pos_b, ee_quat_b = subtract_frame_transforms(root_pos_w, root_quat_w, ee_pos_w, ee_quat_w)
    root_pose_w = torch.cat([root_pos_w, root_quat_w], dim=-1)
    ee_pose_w = torch.cat([ee_pos_w, ee_quat_w], dim=-1)
    ee_pose_b = torch.cat([ee_pos_b, ee_quat_b], dim=-1)

    # the end effector's velocity relative to the root, in the root frame
    relative_vel_w = robot.data.body_vel_w[:, ee_frame_idx, :] - robot.data.root_vel_w
    ee_lin_vel_b = quat_apply_inverse(robot.data.root_quat_w, relative_vel_w[:, 0:3])
    ee_ang_vel_b = quat_apply_inverse(robot.data.root_quat_w, relative_vel_w[:, 3:6])
    ee_vel_b = torch.cat([ee_lin_vel_b, ee_ang_vel_b], dim=-1)

    # the contact force: mean over the sensor's history, the largest of its three components (the
    # tutorial's simplification: the wall is the only thing touched, and the world frame stands in
    # for the root frame)
    contact_forces.update(sim.get_physics_dt())
    ee_force_w, _ = torch.max(torch.mean(contact_forces.data.net_forces_w_history, dim=1), dim=1)
    ee_force_b = ee_force_w

    joint_pos = robot.data.joint_pos[:, arm_joint_ids]
    joint_vel = robot.data.joint_vel[:, arm_joint_ids]
    return (
        jacobian_b,
        mass_matrix,
        gravity,
        ee_pose_b,
        ee_vel_b,
        root_pose_w,
        ee_pose_w,
        ee_force_b,
        joint_pos,
        joint_vel,
    )


def update_target(
    sim: sim_utils.SimulationContext,
    scene: InteractiveScene,
    osc: OperationalSpaceController,
    root_pose_w: torch.Tensor,
    ee_target_set: torch.Tensor,
    current_goal_idx: int,
):
    """The command of the current goal, its pose in the root and world frames, the next goal's index."""
    command = torch.zeros(scene.num_envs, osc.action_dim, device=sim.device)
    command[:] = ee_target_set[current_goal_idx]
    ee_target_pose_b = torch.zeros(scene.num_envs, 7, device=sim.device)
    for target_type in osc.cfg.target_types:
        if target_type == "pose_abs":
            ee_target_pose_b[:] = command[:, :7]
        elif target_type != "wrench_abs":  # a wrench target leaves the pose where it is
            raise ValueError(f"update_target: target type {target_type!r} is not one this tutorial sets")
    ee_target_pos_w, ee_target_quat_w = combine_frame_transforms(
        root_pose_w[:, 0:3], root_pose_w[:, 3:7], ee_target_pose_b[:, 0:3], ee_target_pose_b[:, 3:7]
    )
    ee_target_pose_w = torch.cat([ee_target_pos_w, ee_target_quat_w], dim=-1)
    return command, ee_target_pose_b, ee_target_pose_w, (current_goal_idx + 1) % len(ee_target_set)


def convert_to_task_frame(osc: OperationalSpaceController, command: torch.Tensor, ee_target_pose_b: torch.Tensor):
    """The goal's own frame is the task frame: the pose target becomes the identity in it, and the
    wrench (given in that frame already) stays as it is."""
    command = command.clone()
    task_frame_pose_b = ee_target_pose_b.clone()
    for target_type in osc.cfg.target_types:
        if target_type == "pose_abs":
            command[:, :3], command[:, 3:7] = subtract_frame_transforms(
                task_frame_pose_b[:, :3], task_frame_pose_b[:, 3:], command[:, :3], command[:, 3:7]
            )
        elif target_type != "wrench_abs":
            raise ValueError(f"convert_to_task_frame: target type {target_type!r} is not one this tutorial sets")
    return command, task_frame_pose_b


def main():
    sim_cfg = sim_utils.SimulationCfg(dt=0.01, device=args_cli.device)
    sim = sim_utils.SimulationContext(sim_cfg)
    sim.set_camera_view([2.5, 2.5, 2.5], [0.0, 0.0, 0.0])
    scene_cfg = SceneCfg(num_envs=args_cli.num_envs, env_spacing=2.0)
    scene = InteractiveScene(scene_cfg)
    sim.reset()
    print("[INFO]: Setup complete...")
    run_simulator(sim, scene)


if __name__ == "__main__":
    main()
    simulation_app.close()
