"""Rotation math against SciPy's ``Rotation`` (an independent oracle), with the edge cases.

SciPy orders quaternions ``(x, y, z, w)``; simlab (like Isaac Lab 2.x and MuJoCo) ``(w, x, y, z)``.
Edge cases: identity, antipodal quaternions (``q`` and ``-q``), gimbal lock (pitch = +-pi/2),
half turns (w = 0) and empty batches.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch

import simlab.utils.math as math_utils

Rotation = pytest.importorskip("scipy.spatial.transform").Rotation
Slerp = pytest.importorskip("scipy.spatial.transform").Slerp

N = 256
DT = torch.float64


@pytest.fixture(autouse=True)
def _seed():
    torch.manual_seed(0)
    np.random.seed(0)


def scipy_rot(q_wxyz: torch.Tensor) -> Rotation:
    return Rotation.from_quat(math_utils.convert_quat(q_wxyz, to="xyzw").numpy())


def to_wxyz(rot: Rotation) -> torch.Tensor:
    return math_utils.convert_quat(torch.from_numpy(rot.as_quat()), to="wxyz")


def hard_quats() -> torch.Tensor:
    """Random unit quaternions plus identity, its antipode, half turns and gimbal-lock poses."""
    special = torch.tensor(
        [
            [1.0, 0.0, 0.0, 0.0],  # identity
            [-1.0, 0.0, 0.0, 0.0],  # identity, other sign
            [0.0, 1.0, 0.0, 0.0],  # half turns about x, y, z
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
            [0.0, -0.6, 0.0, 0.8],  # half turn about a tilted axis, w = 0
        ],
        dtype=DT,
    )
    pitch_lock = math_utils.quat_from_euler_xyz(
        torch.tensor([0.3, -1.2], dtype=DT),
        torch.tensor([math.pi / 2, -math.pi / 2], dtype=DT),
        torch.tensor([0.7, 2.0], dtype=DT),
    )
    rand = math_utils.normalize(torch.randn(N, 4, dtype=DT))
    qs = torch.cat((special, pitch_lock, rand, -rand[:8]))  # antipodes of the first few too
    return qs


def assert_same_rotation(q1: torch.Tensor, q2: torch.Tensor, atol: float = 1e-9) -> None:
    # q and -q are the same rotation: compare the matrices
    torch.testing.assert_close(math_utils.matrix_from_quat(q1), math_utils.matrix_from_quat(q2), atol=atol, rtol=0)


# -- conversions -----------------------------------------------------------------------------------


def test_matrix_from_quat_and_back():
    q = hard_quats()
    ours = math_utils.matrix_from_quat(q)
    torch.testing.assert_close(ours, torch.from_numpy(scipy_rot(q).as_matrix()), atol=1e-12, rtol=0)
    back = math_utils.quat_from_matrix(torch.from_numpy(scipy_rot(q).as_matrix()))
    assert_same_rotation(back, q)


def test_quat_from_euler_is_scipy_extrinsic_xyz():
    angles = (torch.rand(N, 3, dtype=DT) * 2 - 1) * math.pi
    angles[0] = torch.tensor([0.4, math.pi / 2, -0.3], dtype=DT)  # gimbal lock
    ours = math_utils.quat_from_euler_xyz(*angles.unbind(-1))
    assert_same_rotation(ours, to_wxyz(Rotation.from_euler("xyz", angles.numpy())))


def test_euler_xyz_from_quat_reconstructs_the_rotation():
    q = hard_quats()
    roll, pitch, yaw = math_utils.euler_xyz_from_quat(q)
    assert (pitch.abs() <= math.pi / 2 + 1e-12).all()
    # at gimbal lock the angles are not unique: the rotation they give must still be the same
    assert_same_rotation(math_utils.quat_from_euler_xyz(roll, pitch, yaw), q, atol=1e-7)
    # away from it they are SciPy's
    away = (pitch.abs() < math.pi / 2 - 1e-3) & (q[:, 0].abs() > 1e-6)
    ref = scipy_rot(q[away]).as_euler("xyz")
    np.testing.assert_allclose(torch.stack((roll, pitch, yaw), -1)[away].numpy(), ref, atol=1e-9)


def test_axis_angle_round_trip_matches_scipy_rotvec():
    q = hard_quats()
    rotvec = math_utils.axis_angle_from_quat(q)
    assert (rotvec.norm(dim=-1) <= math.pi + 1e-9).all()
    assert_same_rotation(math_utils.quat_from_angle_axis(rotvec.norm(dim=-1), rotvec), q)
    ref = torch.from_numpy(scipy_rot(q).as_rotvec())
    # SciPy and simlab may pick opposite vectors for an exact half turn; elsewhere they agree
    not_half = q[:, 0].abs() > 1e-6
    torch.testing.assert_close(rotvec[not_half], ref[not_half], atol=1e-9, rtol=0)
    # antipodal quaternions give the same rotation vector
    torch.testing.assert_close(math_utils.axis_angle_from_quat(-q[not_half]), rotvec[not_half], atol=1e-12, rtol=0)


def test_matrix_from_euler_is_scipy_intrinsic():
    angles = (torch.rand(N, 3, dtype=DT) * 2 - 1) * math.pi
    for convention in ("XYZ", "ZYX", "ZYZ", "XZX"):
        ours = math_utils.matrix_from_euler(angles, convention)
        ref = Rotation.from_euler(convention, angles.numpy()).as_matrix()  # upper case: intrinsic
        np.testing.assert_allclose(ours.numpy(), ref, atol=1e-12)
    with pytest.raises(ValueError, match="repeats an axis"):
        math_utils.matrix_from_euler(angles, "XXY")
    with pytest.raises(ValueError, match="three letters"):
        math_utils.matrix_from_euler(angles, "XYW")


# -- algebra ---------------------------------------------------------------------------------------


def test_quat_mul_apply_and_inverse_match_scipy():
    q1, q2 = hard_quats(), hard_quats().flip(0)
    r1, r2 = scipy_rot(q1), scipy_rot(q2)
    assert_same_rotation(math_utils.quat_mul(q1, q2), to_wxyz(r1 * r2))
    v = torch.randn(q1.shape[0], 3, dtype=DT)
    np.testing.assert_allclose(math_utils.quat_apply(q1, v).numpy(), r1.apply(v.numpy()), atol=1e-12)
    np.testing.assert_allclose(
        math_utils.quat_apply_inverse(q1, v).numpy(), r1.apply(v.numpy(), inverse=True), atol=1e-12
    )
    assert_same_rotation(math_utils.quat_inv(q1), to_wxyz(r1.inv()))


def test_box_minus_and_error_magnitude_match_scipy():
    q1, q2 = hard_quats(), hard_quats().flip(0)
    ref = (scipy_rot(q1) * scipy_rot(q2).inv()).as_rotvec()
    ours = math_utils.quat_box_minus(q1, q2)
    angle = torch.from_numpy(np.linalg.norm(ref, axis=-1))
    torch.testing.assert_close(ours.norm(dim=-1), angle, atol=1e-9, rtol=0)
    torch.testing.assert_close(math_utils.quat_error_magnitude(q1, q2), angle, atol=1e-9, rtol=0)
    not_half = (angle - math.pi).abs() > 1e-6
    np.testing.assert_allclose(ours[not_half].numpy(), ref[not_half.numpy()], atol=1e-9)
    # antipodal inputs: no error at all
    torch.testing.assert_close(
        math_utils.quat_error_magnitude(q1, -q1), torch.zeros(q1.shape[0], dtype=DT), atol=1e-7, rtol=0
    )


def test_box_plus_applies_a_world_frame_rotation_vector():
    q = hard_quats()
    delta = torch.randn(q.shape[0], 3, dtype=DT)
    ours = math_utils.quat_box_plus(q, delta)
    assert (ours[:, 0] >= 0).all()
    assert_same_rotation(ours, to_wxyz(Rotation.from_rotvec(delta.numpy()) * scipy_rot(q)))
    # box minus undoes box plus for steps shorter than pi
    small = delta / delta.norm(dim=-1, keepdim=True) * 0.9 * math.pi * torch.rand(q.shape[0], 1, dtype=DT)
    torch.testing.assert_close(
        math_utils.quat_box_minus(math_utils.quat_box_plus(q, small), q), small, atol=1e-9, rtol=0
    )
    # a zero step is no step
    assert_same_rotation(math_utils.quat_box_plus(q, torch.zeros_like(delta)), q)


def test_slerp_matches_scipy_including_antipodal_and_equal_ends():
    q1, q2 = hard_quats(), hard_quats().flip(0)
    tau = torch.rand(q1.shape[0], dtype=DT)
    ours = math_utils.quat_slerp(q1, q2, tau)
    for i in range(0, q1.shape[0], 17):
        ref = Slerp([0.0, 1.0], scipy_rot(torch.stack((q1[i], q2[i]))))(float(tau[i]))
        assert_same_rotation(ours[i : i + 1], to_wxyz(ref).unsqueeze(0))
    # equal and antipodal end points: the rotation does not move
    assert_same_rotation(math_utils.quat_slerp(q1, q1, tau), q1)
    assert_same_rotation(math_utils.quat_slerp(q1, -q1, tau), q1)
    torch.testing.assert_close(math_utils.quat_slerp(q1, q2, 0.0), q1)


def test_yaw_quat_matches_scipy_heading():
    q = hard_quats()
    away = math_utils.euler_xyz_from_quat(q)[1].abs() < math.pi / 2 - 1e-3
    yaw_ref = scipy_rot(q[away]).as_euler("ZYX")[:, 0]  # heading of intrinsic z-y-x
    yaw = math_utils.axis_angle_from_quat(math_utils.yaw_quat(q[away]))
    np.testing.assert_allclose(yaw[:, 2].numpy(), yaw_ref, atol=1e-9)
    assert torch.allclose(yaw[:, :2], torch.zeros_like(yaw[:, :2]), atol=1e-12)


# -- frames, twists, poses -------------------------------------------------------------------------


def test_pose_error_is_target_relative_to_source():
    t01, t02 = torch.randn(N, 3, dtype=DT), torch.randn(N, 3, dtype=DT)
    q01, q02 = hard_quats()[:N], hard_quats().flip(0)[:N]
    pos_err, rot_err = math_utils.compute_pose_error(t01, q01, t02, q02)
    torch.testing.assert_close(pos_err, t02 - t01)
    # turning the source by the error in the world frame reaches the target
    assert_same_rotation(math_utils.quat_box_plus(q01, rot_err), q02, atol=1e-7)
    _, quat_err = math_utils.compute_pose_error(t01, q01, t02, q02, rot_error_type="quat")
    assert_same_rotation(quat_err, to_wxyz(scipy_rot(q02) * scipy_rot(q01).inv()))
    with pytest.raises(ValueError, match="rot_error_type"):
        math_utils.compute_pose_error(t01, q01, t02, q02, rot_error_type="euler")


def test_apply_delta_pose():
    pos, rot = torch.randn(N, 3, dtype=DT), hard_quats()[:N]
    delta = torch.randn(N, 6, dtype=DT)
    delta[0, 3:] = 0.0  # no rotation
    new_pos, new_rot = math_utils.apply_delta_pose(pos, rot, delta)
    torch.testing.assert_close(new_pos, pos + delta[:, :3])
    assert_same_rotation(new_rot, to_wxyz(Rotation.from_rotvec(delta[:, 3:].numpy()) * scipy_rot(rot)))


def test_rigid_body_twist_transform_against_point_velocities():
    # brute force: the velocity of the point at frame 1's origin is v0 + w0 x t01, seen in frame 1
    v0, w0, t01 = (torch.randn(N, 3, dtype=DT) for _ in range(3))
    q01 = hard_quats()[:N]
    v1, w1 = math_utils.rigid_body_twist_transform(v0, w0, t01, q01)
    r = scipy_rot(q01)
    np.testing.assert_allclose(w1.numpy(), r.apply(w0.numpy(), inverse=True), atol=1e-12)
    np.testing.assert_allclose(
        v1.numpy(), r.apply((v0 + torch.cross(w0, t01, dim=-1)).numpy(), inverse=True), atol=1e-12
    )


def test_skew_symmetric_matrix_is_the_cross_product():
    a, b = torch.randn(N, 3, dtype=DT), torch.randn(N, 3, dtype=DT)
    torch.testing.assert_close(
        (math_utils.skew_symmetric_matrix(a) @ b.unsqueeze(-1)).squeeze(-1), torch.cross(a, b, dim=-1)
    )
    assert math_utils.skew_symmetric_matrix(torch.tensor([1.0, 2.0, 3.0])).shape == (1, 3, 3)


def test_transform_points_and_poses():
    points = torch.randn(4, 10, 3, dtype=DT)
    pos, quat = torch.randn(4, 3, dtype=DT), hard_quats()[:4]
    out = math_utils.transform_points(points, pos, quat)
    for i in range(4):
        ref = scipy_rot(quat[i : i + 1]).apply(points[i].numpy()) + pos[i].numpy()
        np.testing.assert_allclose(out[i].numpy(), ref, atol=1e-12)
    single = math_utils.transform_points(points[0], pos[0], quat[0])
    torch.testing.assert_close(single, out[0])
    pose = math_utils.make_pose(pos, math_utils.matrix_from_quat(quat))
    np.testing.assert_allclose(math_utils.pose_inv(pose).numpy(), np.linalg.inv(pose.numpy()), atol=1e-12)
    back_pos, back_rot = math_utils.unmake_pose(pose)
    torch.testing.assert_close(back_pos, pos)


def test_interpolate_rotations_and_poses_match_scipy():
    r1, r2 = Rotation.random(random_state=1), Rotation.random(random_state=2)
    m1, m2 = torch.from_numpy(r1.as_matrix()), torch.from_numpy(r2.as_matrix())
    ref = Slerp([0.0, 1.0], Rotation.concatenate([r1, r2]))(np.linspace(0, 1, 6)).as_matrix()
    for axis_angle in (True, False):
        np.testing.assert_allclose(math_utils.interpolate_rotations(m1, m2, 5, axis_angle).numpy(), ref, atol=1e-12)
    p1, p2 = torch.zeros(3, dtype=DT), torch.tensor([1.0, 0.0, 0.0], dtype=DT)
    path, n = math_utils.interpolate_poses(math_utils.make_pose(p1, m1), math_utils.make_pose(p2, m2), step_size=0.25)
    assert n == 4 and path.shape == (6, 4, 4)
    np.testing.assert_allclose(path[:, :3, 3].numpy(), np.linspace(p1.numpy(), p2.numpy(), 6), atol=1e-12)
    with pytest.raises(ValueError, match="exactly one"):
        math_utils.interpolate_poses(path[0], path[-1])


def test_camera_conventions_round_trip_and_look_at():
    q = hard_quats()[:32].float()
    for a in ("opengl", "ros", "world"):
        for b in ("opengl", "ros", "world"):
            there = math_utils.convert_camera_frame_orientation_convention(q, a, b)
            back = math_utils.convert_camera_frame_orientation_convention(there, b, a)
            assert_same_rotation(back, q, atol=1e-5)
    # ROS looks along its +z, OpenGL along its -z: the same world direction
    ros = math_utils.convert_camera_frame_orientation_convention(q, "opengl", "ros")
    fwd = torch.tensor([0.0, 0.0, 1.0]).expand(32, 3)
    torch.testing.assert_close(math_utils.quat_apply(ros, fwd), math_utils.quat_apply(q, -fwd), atol=1e-5, rtol=0)
    # a camera at (1, 0, 0) looking at the origin has its -z along -x, and +y along world +z
    rot = math_utils.create_rotation_matrix_from_view(torch.tensor([[1.0, 0.0, 0.0]]), torch.zeros(1, 3))
    torch.testing.assert_close(rot[0] @ torch.tensor([0.0, 0.0, -1.0]), torch.tensor([-1.0, 0.0, 0.0]))
    torch.testing.assert_close(rot[0] @ torch.tensor([0.0, 1.0, 0.0]), torch.tensor([0.0, 0.0, 1.0]))


def test_depth_projection_round_trip():
    k = torch.tensor([[100.0, 0.0, 32.0], [0.0, 110.0, 24.0], [0.0, 0.0, 1.0]], dtype=DT)
    depth = 1.0 + torch.rand(2, 48, 64, dtype=DT)
    points = math_utils.unproject_depth(depth, k)
    assert points.shape == (2, 48 * 64, 3)
    torch.testing.assert_close(points[..., 2], depth.transpose(1, 2).reshape(2, -1))  # u-major order
    pixels = math_utils.project_points(points, k)
    u, v = torch.meshgrid(torch.arange(64, dtype=DT), torch.arange(48, dtype=DT), indexing="ij")
    torch.testing.assert_close(pixels[0, :, 0], u.reshape(-1))
    torch.testing.assert_close(pixels[0, :, 1], v.reshape(-1))
    # perspective depth is the distance to the point; orthogonal depth its z
    perspective = points.norm(dim=-1).reshape(2, 64, 48).transpose(1, 2)
    torch.testing.assert_close(math_utils.orthogonalize_perspective_depth(perspective, k), depth)
    torch.testing.assert_close(math_utils.unproject_depth(perspective, k, is_ortho=False), points)
    assert math_utils.orthogonalize_perspective_depth(perspective[0, ..., None], k).shape == (48, 64, 1)


# -- edge cases: empty batches and misc --------------------------------------------------------------


def test_empty_batches():
    q, v = torch.zeros(0, 4), torch.zeros(0, 3)
    assert math_utils.quat_mul(q, q).shape == (0, 4)
    assert math_utils.quat_apply(q, v).shape == (0, 3)
    assert math_utils.matrix_from_quat(q).shape == (0, 3, 3)
    assert math_utils.quat_from_matrix(torch.zeros(0, 3, 3)).shape == (0, 4)
    assert math_utils.axis_angle_from_quat(q).shape == (0, 3)
    assert math_utils.quat_box_minus(q, q).shape == (0, 3)
    assert math_utils.quat_box_plus(q, v).shape == (0, 4)
    assert math_utils.quat_error_magnitude(q, q).shape == (0,)
    assert all(a.shape == (0,) for a in math_utils.euler_xyz_from_quat(q))
    assert math_utils.matrix_from_euler(v, "XYZ").shape == (0, 3, 3)
    assert math_utils.skew_symmetric_matrix(v).shape == (0, 3, 3)
    assert math_utils.quat_slerp(q, q, 0.5).shape == (0, 4)
    assert math_utils.yaw_quat(q).shape == (0, 4)
    assert math_utils.compute_pose_error(v, q, v, q)[1].shape == (0, 3)
    assert math_utils.rigid_body_twist_transform(v, v, v, q)[0].shape == (0, 3)
    assert math_utils.pose_inv(torch.zeros(0, 4, 4)).shape == (0, 4, 4)
    assert math_utils.random_orientation(0).shape == (0, 4)
    assert math_utils.sample_cylinder(1.0, (0.0, 1.0), 0).shape == (0, 3)


def test_copysign_identity_pose_and_samplers():
    other = torch.tensor([-2.0, 0.0, -0.0, 3.0])
    torch.testing.assert_close(math_utils.copysign(-1.5, other), torch.tensor([-1.5, 1.5, -1.5, 1.5]))
    assert math_utils.is_identity_pose(torch.zeros(5, 3), math_utils.default_orientation(5)) is True
    assert math_utils.is_identity_pose(torch.zeros(5, 3), -math_utils.default_orientation(5)) is False
    tri = math_utils.sample_triangle(1.0, 3.0, (20000,))
    assert tri.min() >= 1.0 and tri.max() <= 3.0 and abs(tri.mean().item() - 2.0) < 0.02
    # a triangle peaking at 2: P(x < 1.5) = 0.5 * 0.5^2 = 0.125
    assert abs((tri < 1.5).float().mean().item() - 0.125) < 0.01
    cyl = math_utils.sample_cylinder(0.5, (-1.0, 2.0), (10, 7))
    assert cyl.shape == (10, 7, 3)
    torch.testing.assert_close(cyl[..., :2].norm(dim=-1), torch.full((10, 7), 0.5))
    assert cyl[..., 2].min() >= -1.0 and cyl[..., 2].max() <= 2.0
    rot = math_utils.generate_random_rotation()
    torch.testing.assert_close(rot @ rot.T, torch.eye(3), atol=1e-6, rtol=0)
    assert math_utils.generate_random_transformation_matrix(pos_boundary=2.0)[:3, 3].abs().max() <= 2.0


def test_convert_quat_numpy_and_errors():
    q = np.array([1.0, 2.0, 3.0, 4.0])
    np.testing.assert_array_equal(math_utils.convert_quat(q, to="xyzw"), [2.0, 3.0, 4.0, 1.0])
    np.testing.assert_array_equal(math_utils.convert_quat(math_utils.convert_quat(q), to="wxyz"), q)
    with pytest.raises(ValueError, match="'xyzw' or 'wxyz'"):
        math_utils.convert_quat(q, to="wzyx")
