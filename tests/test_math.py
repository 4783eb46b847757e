"""Torch math: quaternion algebra against MuJoCo's C implementation, conversions, frames, sampling."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest
import torch

import simlab.utils.math as math_utils

N = 64


@pytest.fixture(autouse=True)
def _seed():
    torch.manual_seed(0)


def rand_quat(n: int = N) -> torch.Tensor:
    # normalized in double precision: MuJoCo's routines assume exactly unit quaternions
    return math_utils.normalize(torch.randn(n, 4, dtype=torch.float64))


def same_rotation(q1: torch.Tensor, q2: torch.Tensor, atol: float = 1e-6) -> bool:
    return torch.allclose(math_utils.quat_unique(q1), math_utils.quat_unique(q2), atol=atol)


# -- against MuJoCo --------------------------------------------------------------------------------


def test_quat_mul_matches_mujoco():
    q1, q2 = rand_quat(), rand_quat()
    ours = math_utils.quat_mul(q1, q2)
    for i in range(N):
        ref = np.zeros(4)
        mujoco.mju_mulQuat(ref, q1[i].numpy(), q2[i].numpy())
        np.testing.assert_allclose(ours[i].numpy(), ref, atol=1e-12)


def test_quat_apply_matches_mujoco():
    q, v = rand_quat(), torch.randn(N, 3, dtype=torch.float64)
    ours = math_utils.quat_apply(q, v)
    ours_inv = math_utils.quat_apply_inverse(q, v)
    for i in range(N):
        ref = np.zeros(3)
        mujoco.mju_rotVecQuat(ref, v[i].numpy(), q[i].numpy())
        np.testing.assert_allclose(ours[i].numpy(), ref, atol=1e-12)
        neg = np.zeros(4)
        mujoco.mju_negQuat(neg, q[i].numpy())
        mujoco.mju_rotVecQuat(ref, v[i].numpy(), neg)
        np.testing.assert_allclose(ours_inv[i].numpy(), ref, atol=1e-12)


def test_matrix_from_quat_matches_mujoco():
    q = rand_quat()
    ours = math_utils.matrix_from_quat(q)
    for i in range(N):
        ref = np.zeros(9)
        mujoco.mju_quat2Mat(ref, q[i].numpy())
        np.testing.assert_allclose(ours[i].numpy(), ref.reshape(3, 3), atol=1e-12)


def test_quat_from_angle_axis_matches_mujoco():
    axis = torch.randn(N, 3, dtype=torch.float64)
    angle = (torch.rand(N, dtype=torch.float64) * 2 - 1) * math.pi
    ours = math_utils.quat_from_angle_axis(angle, axis)
    for i in range(N):
        ref = np.zeros(4)
        a = axis[i].numpy() / np.linalg.norm(axis[i].numpy())
        mujoco.mju_axisAngle2Quat(ref, a, float(angle[i]))
        np.testing.assert_allclose(ours[i].numpy(), ref, atol=1e-12)


# -- identities ------------------------------------------------------------------------------------


def test_aliases():
    assert math_utils.quat_rotate is math_utils.quat_apply
    assert math_utils.quat_rotate_inverse is math_utils.quat_apply_inverse


def test_inverse_and_conjugate():
    q = rand_quat()
    identity = math_utils.default_orientation(N).double()
    assert torch.allclose(math_utils.quat_mul(q, math_utils.quat_conjugate(q)), identity, atol=1e-12)
    scaled = 3.0 * q  # not unit: conjugate is no inverse, quat_inv still is
    assert torch.allclose(math_utils.quat_mul(scaled, math_utils.quat_inv(scaled)), identity, atol=1e-12)


def test_apply_then_inverse_is_identity_with_batch_dims():
    q = math_utils.random_orientation(8 * 5).reshape(8, 5, 4)
    v = torch.randn(8, 5, 3)
    back = math_utils.quat_apply_inverse(q, math_utils.quat_apply(q, v))
    assert back.shape == (8, 5, 3)
    assert torch.allclose(back, v, atol=1e-5)


def test_quat_apply_broadcasts_one_quat_over_vectors():
    q = math_utils.quat_from_angle_axis(torch.tensor(math.pi / 2), torch.tensor([0.0, 0.0, 1.0]))
    v = torch.tensor([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    out = math_utils.quat_apply(q, v)
    assert torch.allclose(out, torch.tensor([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]), atol=1e-6)


def test_quat_apply_keeps_the_vectors_shape_under_a_batch_of_one():
    """Isaac Lab returns ``vec``'s shape: its frame-transformer tutorial rotates a (3,) offset by a (1, 4)
    quaternion and passes ``tuple(result.tolist())`` as a 3-tuple position."""
    q = math_utils.quat_from_euler_xyz(torch.zeros(1), torch.zeros(1), torch.tensor(-math.pi / 2))
    for rotate in (math_utils.quat_apply, math_utils.quat_apply_inverse):
        out = rotate(q, torch.tensor([1.0, 0.0, 0.0]))
        assert out.shape == (3,)
        assert torch.allclose(
            out, torch.tensor([0.0, -1.0 if rotate is math_utils.quat_apply else 1.0, 0.0]), atol=1e-6
        )
    assert math_utils.quat_apply(q, torch.ones(5, 3)).shape == (5, 3)  # broadcasting is kept
    assert math_utils.quat_apply(torch.ones(4, 1, 4), torch.ones(4, 2, 3)).shape == (4, 2, 3)


def test_bad_quaternion_shape_errors():
    with pytest.raises(ValueError, match="last dimension 4"):
        math_utils.quat_mul(torch.zeros(3, 3), torch.zeros(3, 4))


def test_matrix_round_trip():
    q = rand_quat(1000)
    # include the hard cases: 180 degree turns about each axis (w = 0)
    q[:3] = torch.tensor([[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]], dtype=q.dtype)
    back = math_utils.quat_from_matrix(math_utils.matrix_from_quat(q))
    assert same_rotation(back, q, atol=1e-9)
    # and the matrix is a rotation
    m = math_utils.matrix_from_quat(q)
    eye = torch.eye(3, dtype=q.dtype).expand_as(m)
    assert torch.allclose(m @ m.transpose(-1, -2), eye, atol=1e-12)


def test_euler_round_trip():
    roll = (torch.rand(N, dtype=torch.float64) * 2 - 1) * math.pi
    pitch = (torch.rand(N, dtype=torch.float64) * 2 - 1) * (math.pi / 2 - 0.05)
    yaw = (torch.rand(N, dtype=torch.float64) * 2 - 1) * math.pi
    q = math_utils.quat_from_euler_xyz(roll, pitch, yaw)
    r2, p2, y2 = math_utils.euler_xyz_from_quat(q)
    assert torch.allclose(r2, roll, atol=1e-9)
    assert torch.allclose(p2, pitch, atol=1e-9)
    assert torch.allclose(y2, yaw, atol=1e-9)
    r3, _, y3 = math_utils.euler_xyz_from_quat(q, wrap_to_2pi=True)
    assert (r3 >= 0).all() and (y3 < 2 * math.pi).all()
    assert torch.allclose(math_utils.wrap_to_pi(r3), roll, atol=1e-9)


def test_euler_is_extrinsic_xyz():
    roll, pitch, yaw = torch.tensor(0.3), torch.tensor(-0.7), torch.tensor(1.1)
    x, y, z = torch.eye(3)
    qx = math_utils.quat_from_angle_axis(roll, x)
    qy = math_utils.quat_from_angle_axis(pitch, y)
    qz = math_utils.quat_from_angle_axis(yaw, z)
    expected = math_utils.quat_mul(qz, math_utils.quat_mul(qy, qx))
    assert torch.allclose(math_utils.quat_from_euler_xyz(roll, pitch, yaw), expected, atol=1e-6)


def test_axis_angle_and_error_magnitude():
    axis = math_utils.normalize(torch.randn(N, 3, dtype=torch.float64))
    angle = torch.rand(N, dtype=torch.float64) * math.pi
    q = math_utils.quat_from_angle_axis(angle, axis)
    assert torch.allclose(math_utils.axis_angle_from_quat(q), axis * angle[:, None], atol=1e-9)
    assert torch.allclose(math_utils.axis_angle_from_quat(-q), axis * angle[:, None], atol=1e-9)
    # tiny angles: no 0/0
    small = math_utils.quat_from_angle_axis(torch.full((N,), 1e-9, dtype=torch.float64), axis)
    assert torch.isfinite(math_utils.axis_angle_from_quat(small)).all()
    q2 = rand_quat()
    err = math_utils.quat_error_magnitude(math_utils.quat_mul(q, q2), q2)
    assert torch.allclose(err, angle, atol=1e-7)


def test_yaw_quat_keeps_heading_only():
    yaw = torch.tensor([0.4, -2.0, 3.0], dtype=torch.float64)
    q = math_utils.quat_from_euler_xyz(
        torch.tensor([0.2, -0.3, 0.5]).double(), torch.tensor([0.1, 0.4, -0.2]).double(), yaw
    )
    yq = math_utils.yaw_quat(q)
    r, p, y = math_utils.euler_xyz_from_quat(yq)
    assert torch.allclose(r, torch.zeros(3, dtype=torch.float64), atol=1e-12)
    assert torch.allclose(p, torch.zeros(3, dtype=torch.float64), atol=1e-12)
    assert torch.allclose(y, yaw, atol=1e-9)


def test_quat_unique():
    q = rand_quat()
    u = math_utils.quat_unique(q)
    assert (u[:, 0] >= 0).all()
    assert torch.allclose(u.abs(), q.abs())


def test_frame_transforms_round_trip():
    t01, q01 = torch.randn(N, 3, dtype=torch.float64), rand_quat()
    t12, q12 = torch.randn(N, 3, dtype=torch.float64), rand_quat()
    t02, q02 = math_utils.combine_frame_transforms(t01, q01, t12, q12)
    # a point p in frame 2 lands at the same world point both ways
    p = torch.randn(N, 3, dtype=torch.float64)
    via_1 = t01 + math_utils.quat_apply(q01, t12 + math_utils.quat_apply(q12, p))
    assert torch.allclose(t02 + math_utils.quat_apply(q02, p), via_1, atol=1e-10)
    t12b, q12b = math_utils.subtract_frame_transforms(t01, q01, t02, q02)
    assert torch.allclose(t12b, t12, atol=1e-10)
    assert same_rotation(q12b, q12, atol=1e-10)
    # frame 0 seen from frame 1
    t10, q10 = math_utils.subtract_frame_transforms(t01, q01)
    tz, qz = math_utils.combine_frame_transforms(t01, q01, t10, q10)
    assert torch.allclose(tz, torch.zeros_like(tz), atol=1e-10)
    assert same_rotation(qz, math_utils.default_orientation(N).double(), atol=1e-10)


# -- scalar helpers --------------------------------------------------------------------------------


def test_wrap_to_pi():
    # MATLAB's wrapToPi: odd multiples of pi keep their sign
    a = torch.tensor([0.0, math.pi, -math.pi, 3 * math.pi, -3 * math.pi, 2 * math.pi + 0.5, -0.5, 4 * math.pi])
    out = math_utils.wrap_to_pi(a)
    expected = torch.tensor([0.0, math.pi, -math.pi, math.pi, -math.pi, 0.5, -0.5, 0.0])
    assert torch.allclose(out, expected, atol=1e-6)
    big = torch.linspace(-20, 20, 101)
    w = math_utils.wrap_to_pi(big)
    assert (w >= -math.pi - 1e-6).all() and (w <= math.pi + 1e-6).all()
    assert torch.allclose(torch.sin(w), torch.sin(big), atol=1e-5)


def test_saturate_and_scale():
    x = torch.tensor([-5.0, 0.5, 5.0])
    assert torch.equal(math_utils.saturate(x, -1.0, 1.0), torch.tensor([-1.0, 0.5, 1.0]))
    lo, hi = torch.tensor([0.0, 0.0, 0.0]), torch.tensor([1.0, 2.0, 3.0])
    assert torch.equal(math_utils.saturate(x, lo, hi), torch.tensor([0.0, 0.5, 3.0]))
    y = torch.tensor([0.0, 1.0, 2.0])
    s = math_utils.scale_transform(y, torch.tensor(0.0), torch.tensor(2.0))
    assert torch.allclose(s, torch.tensor([-1.0, 0.0, 1.0]))
    assert torch.allclose(math_utils.unscale_transform(s, torch.tensor(0.0), torch.tensor(2.0)), y)


# -- sampling --------------------------------------------------------------------------------------


def test_sample_uniform_shapes_and_bounds():
    s = math_utils.sample_uniform(-2.0, 3.0, 10000, "cpu")
    assert s.shape == (10000,) and s.min() >= -2.0 and s.max() < 3.0
    assert abs(s.mean().item() - 0.5) < 0.1
    lower, upper = torch.tensor([0.0, 10.0]), torch.tensor([1.0, 20.0])
    t = math_utils.sample_uniform(lower, upper, (500, 2), "cpu")
    assert t.shape == (500, 2)
    assert (t[:, 0] < 1.0).all() and (t[:, 1] >= 10.0).all()
    with pytest.raises(TypeError, match="size"):
        math_utils.sample_uniform(0.0, 1.0, 2.5, "cpu")


def test_sample_gaussian_and_log_uniform():
    g = math_utils.sample_gaussian(1.0, 0.5, (20000,), "cpu")
    assert abs(g.mean().item() - 1.0) < 0.02 and abs(g.std().item() - 0.5) < 0.02
    lu = math_utils.sample_log_uniform(1e-3, 1e1, 20000, "cpu")
    assert lu.min() >= 1e-3 and lu.max() < 1e1
    assert abs(torch.log10(lu).mean().item() - (-1.0)) < 0.05  # uniform in log space
    with pytest.raises(ValueError, match="positive"):
        math_utils.sample_log_uniform(0.0, 1.0, 4)


def test_orientations():
    d = math_utils.default_orientation(4)
    assert torch.equal(d, torch.tensor([[1.0, 0, 0, 0]] * 4))
    r = math_utils.random_orientation(1000)
    assert torch.allclose(r.norm(dim=-1), torch.ones(1000), atol=1e-5)
    # uniform over SO(3): each component has mean ~0
    assert r.mean(dim=0).abs().max() < 0.1
    y = math_utils.random_yaw_orientation(1000)
    assert torch.allclose(y[:, 1:3], torch.zeros(1000, 2))
    assert torch.allclose(y.norm(dim=-1), torch.ones(1000), atol=1e-6)
    yaw = math_utils.euler_xyz_from_quat(y)[2]
    assert yaw.min() < -2.5 and yaw.max() > 2.5


def test_convert_quat():
    q = torch.tensor([1.0, 2.0, 3.0, 4.0])
    assert torch.equal(math_utils.convert_quat(q, "xyzw"), torch.tensor([2.0, 3.0, 4.0, 1.0]))
    assert torch.equal(math_utils.convert_quat(math_utils.convert_quat(q, "xyzw"), "wxyz"), q)
    with pytest.raises(ValueError, match="'xyzw' or 'wxyz'"):
        math_utils.convert_quat(q, "zyx")


def test_constant_tensor_is_made_once_per_value_and_device():
    from simlab.utils.math import constant_tensor

    ranges = constant_tensor([(0.0, 1.0), [-2, 3]], "cpu")
    assert ranges.dtype == torch.float32 and ranges.tolist() == [[0.0, 1.0], [-2.0, 3.0]]
    assert constant_tensor(((0, 1), (-2.0, 3.0)), torch.device("cpu")) is ranges  # equal numbers, same tensor
    assert constant_tensor([(0.0, 1.5), (-2.0, 3.0)], "cpu") is not ranges


# Isaac Lab compiles these with @torch.jit.script, so a task's own scripted functions call them.
def _scripted_math_calls() -> dict[str, tuple]:
    q, q2 = rand_quat(8).float(), rand_quat(8).float()
    v, v2 = torch.randn(8, 3), torch.randn(8, 3)
    angles = torch.randn(8)
    points, depth = torch.randn(8, 5, 3), torch.rand(2, 6, 7) + 0.5
    intrinsics = torch.tensor([[[50.0, 0.0, 3.5], [0.0, 50.0, 3.0], [0.0, 0.0, 1.0]]]).repeat(2, 1, 1)
    return {
        "scale_transform": (v, -torch.ones(3), torch.ones(3) * 2),
        "unscale_transform": (v, -torch.ones(3), torch.ones(3) * 2),
        "saturate": (v, -torch.ones(3) * 0.5, torch.ones(3) * 0.5),
        "normalize": (v,),
        "wrap_to_pi": (angles * 10,),
        "copysign": (2.0, angles),
        "quat_unique": (q,),
        "matrix_from_quat": (q,),
        "quat_conjugate": (q,),
        "quat_inv": (q,),
        "quat_from_euler_xyz": (angles, angles * 0.5, -angles),
        "quat_from_matrix": (math_utils.matrix_from_quat(q),),
        "euler_xyz_from_quat": (q,),
        "axis_angle_from_quat": (q,),
        "quat_from_angle_axis": (angles, v),
        "quat_mul": (q, q2),
        "yaw_quat": (q,),
        "quat_box_minus": (q, q2),
        "quat_box_plus": (q, v * 0.3),
        "quat_apply": (q, v),
        "quat_apply_inverse": (q, v),
        "quat_rotate": (q, v),
        "quat_rotate_inverse": (q, v),
        "quat_apply_yaw": (q, v),
        "quat_error_magnitude": (q, q2),
        "skew_symmetric_matrix": (v,),
        "combine_frame_transforms": (v, q, v2, q2),
        "subtract_frame_transforms": (v, q, v2, q2),
        "compute_pose_error": (v, q, v2, q2),
        "apply_delta_pose": (v, q, torch.cat((v2, v2 * 0.2), dim=-1)),
        "transform_points": (points, v, q),
        "orthogonalize_perspective_depth": (depth, intrinsics),
        "unproject_depth": (depth, intrinsics),
        "project_points": (points[:2], intrinsics),
    }


@pytest.mark.parametrize("name", sorted(_scripted_math_calls()))
def test_the_functions_isaac_lab_scripts_compile_with_torchscript_and_agree(name):
    function = getattr(math_utils, name)
    args = _scripted_math_calls()[name]
    eager, scripted = function(*args), torch.jit.script(function)(*args)
    for a, b in zip(*((r,) if isinstance(r, torch.Tensor) else r for r in (eager, scripted))):
        assert torch.allclose(a, b, atol=1e-5), (a, b)


@torch.jit.script
def _heading_and_up(root_quat: torch.Tensor, target_dir: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    # a task's own TorchScript, the way Isaac Lab's locomotion and AMP tasks write theirs
    forward = math_utils.quat_apply(math_utils.yaw_quat(root_quat), torch.tensor([1.0, 0.0, 0.0]).expand_as(target_dir))
    up = math_utils.quat_apply(root_quat, torch.tensor([0.0, 0.0, 1.0]).expand_as(target_dir))
    return (forward * target_dir).sum(-1), up[:, 2]


def test_a_tasks_scripted_function_calls_the_math_functions():
    quat = math_utils.quat_from_euler_xyz(torch.zeros(2), torch.zeros(2), torch.tensor([0.0, math.pi / 2]))
    heading, up = _heading_and_up(quat, torch.tensor([[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]))
    assert torch.allclose(heading, torch.tensor([1.0, 0.0]), atol=1e-6)
    assert torch.allclose(up, torch.ones(2))
