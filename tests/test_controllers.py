"""Task-space controllers on the Franka arm: differential IK reaches poses, operational-space control
tracks a setpoint under gravity, and bad commands or configs are refused with the fix named."""

from __future__ import annotations

import pytest
import torch
from conftest import DEVICES
from test_franka_dynamics import make_scene, step

from simlab.controllers import (
    DifferentialIKController,
    DifferentialIKControllerCfg,
    OperationalSpaceController,
    OperationalSpaceControllerCfg,
)
from simlab.robots.franka import FRANKA_PANDA_CFG, FRANKA_PANDA_HIGH_PD_CFG
from simlab.utils.math import quat_error_magnitude, subtract_frame_transforms


def arm_state(robot, hand: int, arm: list[int]):
    """Hand pose in the root frame, its Jacobian over the arm joints, the arm joint positions."""
    pos_b, quat_b = subtract_frame_transforms(
        robot.data.root_pos_w, robot.data.root_quat_w, robot.data.body_pos_w[:, hand], robot.data.body_quat_w[:, hand]
    )
    jacobian = robot.root_physx_view.get_jacobians()[:, hand - 1, :, arm]
    return pos_b, quat_b, jacobian, robot.data.joint_pos[:, arm]


def reachable_targets(robot, hand: int, arm: list[int], seed: int):
    """Hand poses of random arm configurations within 0.4 rad of the current one: reachable by construction."""
    start = robot.data.joint_pos.clone()
    noise = torch.rand(start.shape, generator=torch.Generator().manual_seed(seed)) * 0.8 - 0.4
    q = start + noise.to(start.device)
    q[:, 7:] = start[:, 7:]
    limits = robot.data.soft_joint_pos_limits
    q = torch.minimum(torch.maximum(q, limits[..., 0]), limits[..., 1])
    robot.write_joint_position_to_sim(q)
    pos, quat, _, _ = arm_state(robot, hand, arm)
    robot.write_joint_position_to_sim(start)
    return pos.clone(), quat.clone()


@pytest.mark.parametrize("method", ["dls", "pinv", "svd"])
def test_differential_ik_reaches_a_reachable_pose_within_a_millimetre(method):
    sim, scene = make_scene("cpu", num_envs=3, robot_cfg=FRANKA_PANDA_HIGH_PD_CFG, dt=1.0 / 60.0)
    robot = scene["robot"]
    hand, arm = robot.find_bodies("panda_hand")[0][0], robot.find_joints("panda_joint.*")[0]
    target_pos, target_quat = reachable_targets(robot, hand, arm, seed=3)
    ik = DifferentialIKController(
        DifferentialIKControllerCfg(command_type="pose", ik_method=method), robot.num_instances, "cpu"
    )
    ik.set_command(torch.cat([target_pos, target_quat], dim=-1))
    for _ in range(300):
        pos, quat, jac, q = arm_state(robot, hand, arm)
        robot.set_joint_position_target(ik.compute(pos, quat, jac, q), joint_ids=arm)
        step(sim, scene)
    pos, quat, _, _ = arm_state(robot, hand, arm)
    assert (pos - target_pos).norm(dim=-1).max() < 1e-3
    assert quat_error_magnitude(quat, target_quat).max() < 1e-2


def test_relative_position_ik_moves_by_the_commanded_offset():
    sim, scene = make_scene("cpu", num_envs=2, robot_cfg=FRANKA_PANDA_HIGH_PD_CFG, dt=1.0 / 60.0)
    robot = scene["robot"]
    hand, arm = robot.find_bodies("panda_hand")[0][0], robot.find_joints("panda_joint.*")[0]
    ik = DifferentialIKController(
        DifferentialIKControllerCfg(command_type="position", use_relative_mode=True, ik_method="dls"), 2, "cpu"
    )
    assert ik.action_dim == 3
    start, quat, _, _ = arm_state(robot, hand, arm)
    offset = torch.tensor([[0.05, -0.03, 0.04], [-0.04, 0.05, -0.05]])
    ik.set_command(offset, ee_pos=start, ee_quat=quat)
    for _ in range(200):
        pos, quat, jac, q = arm_state(robot, hand, arm)
        robot.set_joint_position_target(ik.compute(pos, quat, jac, q), joint_ids=arm)
        step(sim, scene)
    torch.testing.assert_close(arm_state(robot, hand, arm)[0] - start, offset, atol=1e-3, rtol=0)


def test_jacobian_transpose_ik_reduces_the_error():
    sim, scene = make_scene("cpu", num_envs=1, robot_cfg=FRANKA_PANDA_HIGH_PD_CFG, dt=1.0 / 60.0)
    robot = scene["robot"]
    hand, arm = robot.find_bodies("panda_hand")[0][0], robot.find_joints("panda_joint.*")[0]
    start, quat, _, _ = arm_state(robot, hand, arm)
    ik = DifferentialIKController(DifferentialIKControllerCfg(command_type="position", ik_method="trans"), 1, "cpu")
    ik.set_command(start + torch.tensor([[0.05, 0.05, -0.05]]), ee_quat=quat)
    initial = 0.05 * 3**0.5
    for _ in range(200):
        pos, quat, jac, q = arm_state(robot, hand, arm)
        robot.set_joint_position_target(ik.compute(pos, quat, jac, q), joint_ids=arm)
        step(sim, scene)
    assert ik.position_error.norm() < 0.5 * initial  # slow (the step is J^T dx), but it goes the right way


def test_unreachable_pose_leaves_a_finite_remaining_error():
    sim, scene = make_scene("cpu", num_envs=2, robot_cfg=FRANKA_PANDA_HIGH_PD_CFG, dt=1.0 / 60.0)
    robot = scene["robot"]
    hand, arm = robot.find_bodies("panda_hand")[0][0], robot.find_joints("panda_joint.*")[0]
    ik = DifferentialIKController(DifferentialIKControllerCfg(command_type="pose", ik_method="dls"), 2, "cpu")
    far = torch.tensor([[3.0, 0.0, 0.5, 0.0, 1.0, 0.0, 0.0]]).repeat(2, 1)  # 3 m away: the arm reaches 0.85 m
    ik.set_command(far)
    for _ in range(120):
        pos, quat, jac, q = arm_state(robot, hand, arm)
        targets = ik.compute(pos, quat, jac, q)
        assert torch.isfinite(targets).all()
        robot.set_joint_position_target(targets, joint_ids=arm)
        step(sim, scene)
    remaining = ik.position_error.norm(dim=-1)
    assert torch.isfinite(remaining).all() and (remaining > 2.0).all()
    assert torch.isfinite(robot.data.joint_pos).all()


def test_absolute_targets_take_the_direction_of_the_quaternion():
    """A policy's 4 orientation numbers are not unit length; the rotation they mean is their direction
    (unnormalized, the axis-angle error, and so the joint step, would grow with their length)."""
    jac = torch.eye(6, 7).repeat(2, 1, 1)
    pos, quat, q = torch.zeros(2, 3), torch.tensor([[1.0, 0.0, 0.0, 0.0]]).repeat(2, 1), torch.zeros(2, 7)
    unit = torch.tensor([[0.2, 0.0, 0.3, 0.9539392, 0.0, 0.0, 0.3]]).repeat(2, 1)
    scaled = unit.clone()
    scaled[0, 3:] *= 3.0
    scaled[1, 3:] *= 0.2
    steps = []
    for command in (unit, scaled):
        ik = DifferentialIKController(DifferentialIKControllerCfg(command_type="pose", ik_method="dls"), 2, "cpu")
        ik.set_command(command)
        steps.append(ik.compute(pos, quat, jac, q))
    torch.testing.assert_close(steps[1], steps[0])
    osc = OperationalSpaceController(OperationalSpaceControllerCfg(target_types=["pose_abs"]), 2, "cpu")
    osc.set_command(scaled)
    torch.testing.assert_close(osc.desired_ee_pose_b, unit)


def test_wrench_targets_and_axes_are_given_in_the_task_frame_and_closed_on_the_measured_force():
    """10 N along the task frame's z, which is the root frame's -y (turned 90 degrees about x): the
    efforts are J^T of that force; with contact stiffness 0.5, a measured 4 N adds 0.5 (10 - 4) N."""
    jac = torch.eye(6, 7).repeat(2, 1, 1)  # efforts = the task-space force, padded
    turned = torch.tensor([[0.0, 0.0, 0.0, 0.70710678, 0.70710678, 0.0, 0.0]]).repeat(2, 1)
    command = torch.tensor([[0.0, 0.0, 10.0, 0.0, 0.0, 0.0]]).repeat(2, 1)
    cfg = OperationalSpaceControllerCfg(
        target_types=["wrench_abs"], contact_wrench_control_axes_task=[0, 0, 1, 0, 0, 0]
    )
    osc = OperationalSpaceController(cfg, 2, "cpu")
    osc.set_command(command, current_task_frame_pose_b=turned)
    torch.testing.assert_close(osc.compute(jac)[:, :3], torch.tensor([[0.0, -10.0, 0.0]]).repeat(2, 1))
    cfg.contact_wrench_stiffness_task = [0.0, 0.0, 0.5, 0.0, 0.0, 0.0]
    closed = OperationalSpaceController(cfg, 2, "cpu")
    closed.set_command(command, current_task_frame_pose_b=turned)
    with pytest.raises(ValueError, match="current_ee_force_b"):
        closed.compute(jac)
    measured = torch.tensor([[0.0, -4.0, 0.0], [0.0, -10.0, 0.0]])
    efforts = closed.compute(jac, current_ee_force_b=measured)
    torch.testing.assert_close(efforts[:, :3], torch.tensor([[0.0, -13.0, 0.0], [0.0, -10.0, 0.0]]))


@pytest.mark.parametrize("device", DEVICES)
def test_operational_space_control_tracks_a_setpoint_under_gravity(device):
    robot_cfg = FRANKA_PANDA_CFG.copy()
    robot_cfg.actuators["panda_shoulder"].stiffness = 0.0
    robot_cfg.actuators["panda_shoulder"].damping = 0.0
    robot_cfg.actuators["panda_forearm"].stiffness = 0.0
    robot_cfg.actuators["panda_forearm"].damping = 0.0
    sim, scene = make_scene(device, num_envs=2, robot_cfg=robot_cfg, dt=0.005)
    robot = scene["robot"]
    hand, arm = robot.find_bodies("panda_hand")[0][0], robot.find_joints("panda_joint.*")[0]
    osc = OperationalSpaceController(
        OperationalSpaceControllerCfg(
            target_types=["pose_abs"],
            impedance_mode="fixed",
            inertial_dynamics_decoupling=True,
            gravity_compensation=True,
            motion_stiffness_task=150.0,
            motion_damping_ratio_task=1.0,
            nullspace_control="position",
        ),
        2,
        device,
    )
    assert osc.action_dim == 7
    start, quat, _, _ = arm_state(robot, hand, arm)
    target = torch.cat(
        [start + torch.tensor([[0.08, -0.05, 0.06], [-0.05, 0.1, -0.04]], device=start.device), quat], -1
    )
    osc.set_command(target)
    view = robot.root_physx_view
    posture = robot.data.default_joint_pos[:, arm]
    for _ in range(600):  # 3 s
        pos, quat, jac, q = arm_state(robot, hand, arm)
        vel = torch.cat([robot.data.body_lin_vel_w[:, hand], robot.data.body_ang_vel_w[:, hand]], dim=-1)
        mass = view.get_generalized_mass_matrices()[:, arm][:, :, arm]
        gravity = view.get_gravity_compensation_forces()[:, arm]
        efforts = osc.compute(
            jac,
            current_ee_pose_b=torch.cat([pos, quat], -1),
            current_ee_vel_b=vel,
            mass_matrix=mass,
            gravity=gravity,
            current_joint_pos=q,
            current_joint_vel=robot.data.joint_vel[:, arm],
            nullspace_joint_pos_target=posture,
        )
        robot.set_joint_effort_target(efforts, joint_ids=arm)
        step(sim, scene)
    pos, quat, _, _ = arm_state(robot, hand, arm)
    assert (pos - target[:, :3]).norm(dim=-1).max() < 5e-3
    assert quat_error_magnitude(quat, target[:, 3:]).max() < 0.02


def test_operational_space_control_without_gravity_compensation_sags():
    """The same setpoint without gravity compensation is held off by gravity: the term matters."""
    robot_cfg = FRANKA_PANDA_CFG.copy()
    for group in ("panda_shoulder", "panda_forearm"):
        robot_cfg.actuators[group].stiffness = 0.0
        robot_cfg.actuators[group].damping = 0.0
    sim, scene = make_scene("cpu", num_envs=1, robot_cfg=robot_cfg, dt=0.005)
    robot = scene["robot"]
    hand, arm = robot.find_bodies("panda_hand")[0][0], robot.find_joints("panda_joint.*")[0]
    osc = OperationalSpaceController(
        OperationalSpaceControllerCfg(target_types=["pose_abs"], motion_stiffness_task=100.0), 1, "cpu"
    )
    start, quat, _, _ = arm_state(robot, hand, arm)
    osc.set_command(torch.cat([start, quat], -1))
    for _ in range(400):
        pos, quat, jac, q = arm_state(robot, hand, arm)
        vel = torch.cat([robot.data.body_lin_vel_w[:, hand], robot.data.body_ang_vel_w[:, hand]], dim=-1)
        robot.set_joint_effort_target(osc.compute(jac, torch.cat([pos, quat], -1), vel), joint_ids=arm)
        step(sim, scene)
    assert (arm_state(robot, hand, arm)[0] - start)[0, 2] < -0.02


def test_variable_impedance_reads_gains_from_the_command():
    osc = OperationalSpaceController(
        OperationalSpaceControllerCfg(target_types=["pose_rel"], impedance_mode="variable"), 2, "cpu"
    )
    assert osc.action_dim == 18
    command = torch.zeros(2, 18)
    command[:, 6:12] = 5000.0  # clipped to the stiffness limit
    command[:, 12:18] = 0.5
    pose = torch.tensor([[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]]).repeat(2, 1)
    osc.set_command(command, current_ee_pose_b=pose)
    assert (osc._kp == 1000.0).all() and (osc._damping_ratio == 0.5).all()


def test_commands_of_the_wrong_size_are_refused():
    ik = DifferentialIKController(DifferentialIKControllerCfg(command_type="pose", ik_method="dls"), 2, "cpu")
    with pytest.raises(ValueError, match=r"\(num_envs, 7\).*x, y, z, qw, qx, qy, qz.*got \(2, 6\)"):
        ik.set_command(torch.zeros(2, 6))
    osc = OperationalSpaceController(OperationalSpaceControllerCfg(target_types=["pose_abs"]), 2, "cpu")
    with pytest.raises(ValueError, match=r"\(num_envs, 7\), got \(2, 3\)"):
        osc.set_command(torch.zeros(2, 3))


def test_bad_controller_configs_name_the_choices():
    with pytest.raises(ValueError, match="use one of \\('pinv', 'svd', 'trans', 'dls'\\)"):
        DifferentialIKControllerCfg(command_type="pose", ik_method="newton")
    with pytest.raises(ValueError, match="use one of \\('position', 'pose'\\)"):
        DifferentialIKControllerCfg(command_type="position_rel", ik_method="dls")
    with pytest.raises(ValueError, match="do not apply to ik_method 'dls'"):
        DifferentialIKControllerCfg(command_type="pose", ik_method="dls", ik_params={"k_val": 2.0})
    with pytest.raises(ValueError, match="each must be one of"):
        OperationalSpaceControllerCfg(target_types=["pose"])


def test_small_spd_solves_match_torch():
    from simlab.controllers.linalg import inverse_spd, solve_spd, solve_spd_unrolled

    gen = torch.Generator().manual_seed(0)
    for n in (3, 6, 7):
        m = torch.randn(16, n, n, generator=gen, dtype=torch.float64)
        a = m @ m.transpose(-1, -2) + 0.1 * torch.eye(n, dtype=torch.float64)
        b = torch.randn(16, n, 2, generator=gen, dtype=torch.float64)
        # the CPU's LAPACK path and the unrolled one a CUDA graph replays
        torch.testing.assert_close(solve_spd(a, b), torch.linalg.solve(a, b))
        torch.testing.assert_close(solve_spd_unrolled(a, b), torch.linalg.solve(a, b))
        torch.testing.assert_close(inverse_spd(a), torch.linalg.inv(a))
    # singular: LAPACK refuses it, the unrolled solve clamps the pivot: finite
    singular = torch.zeros(2, 6, 6)
    singular[:, 0, 0] = 1.0
    assert torch.isfinite(solve_spd(singular, torch.ones(2, 6, 1))).all()
