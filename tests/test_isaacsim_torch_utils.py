"""Isaac Sim's torch helpers under ``simlab.utils.torch_utils`` (Isaac Lab 2.x task files import them)."""

from __future__ import annotations

import math

import torch

import simlab.utils.math as math_utils
import simlab.utils.torch_utils as torch_utils
from simlab.utils.torch_utils.rotations import compute_heading_and_up, compute_rot


def test_scaling_and_clamping():
    lower, upper = torch.tensor([-2.0, 0.0]), torch.tensor([2.0, 1.0])
    x = torch.tensor([[1.0, 0.25]])
    torch.testing.assert_close(torch_utils.maths.unscale(x, lower, upper), torch.tensor([[0.5, -0.5]]))
    torch.testing.assert_close(torch_utils.scale(torch_utils.unscale(x, lower, upper), lower, upper), x)
    clamped = torch_utils.tensor_clamp(torch.tensor([[-3.0, 2.0]]), lower, upper)
    torch.testing.assert_close(clamped, torch.tensor([[-2.0, 1.0]]))
    draws = torch_utils.torch_rand_float(-1.0, 3.0, (1000, 1), "cpu")
    assert draws.shape == (1000, 1) and draws.min() >= -1.0 and draws.max() < 3.0 and draws.std() > 0.5


def test_transforms_combine_and_invert():
    q = math_utils.quat_from_euler_xyz(torch.tensor([0.3]), torch.tensor([-0.2]), torch.tensor([1.1]))
    t = torch.tensor([[1.0, 2.0, 3.0]])
    q_inv, t_inv = torch_utils.tf_inverse(q, t)
    q_id, t_zero = torch_utils.tf_combine(q, t, q_inv, t_inv)
    torch.testing.assert_close(q_id.abs(), torch.tensor([[1.0, 0.0, 0.0, 0.0]]), atol=1e-6, rtol=0)
    torch.testing.assert_close(t_zero, torch.zeros(1, 3), atol=1e-6, rtol=0)
    point = torch.tensor([[0.5, -1.0, 0.0]])
    torch.testing.assert_close(torch_utils.tf_apply(q, t, point), math_utils.quat_apply(q, point) + t)


def test_locomotion_helpers_of_a_torso_turned_to_face_left():
    # a torso yawed 90 deg (facing +y), upright, its target straight ahead along +y
    yaw = torch.tensor([math.pi / 2])
    torso = math_utils.quat_from_euler_xyz(torch.zeros(1), torch.zeros(1), yaw)
    identity = torch.tensor([[1.0, 0.0, 0.0, 0.0]])
    heading_axis, up_axis = torch.tensor([[1.0, 0.0, 0.0]]), torch.tensor([[0.0, 0.0, 1.0]])
    to_target = torch.tensor([[0.0, 5.0, 0.0]])
    torso_quat, up_proj, heading_proj, up_vec, heading_vec = compute_heading_and_up(
        torso, identity, to_target, heading_axis, up_axis, 2
    )
    torch.testing.assert_close(up_proj, torch.ones(1))
    torch.testing.assert_close(heading_proj, torch.ones(1))
    torch.testing.assert_close(heading_vec, torch.tensor([[0.0, 1.0, 0.0]]), atol=1e-6, rtol=0)
    velocity = torch.tensor([[0.0, 2.0, 0.0]])  # moving forward, in the world frame
    vel_loc, angvel_loc, roll, pitch, torso_yaw, angle_to_target = compute_rot(
        torso_quat, velocity, torch.zeros(1, 3), to_target, torch.zeros(1, 3)
    )
    torch.testing.assert_close(vel_loc, torch.tensor([[2.0, 0.0, 0.0]]), atol=1e-6, rtol=0)  # forward in the torso
    torch.testing.assert_close(torso_yaw, yaw)
    torch.testing.assert_close(angle_to_target, torch.zeros(1), atol=1e-6, rtol=0)
    torch.testing.assert_close(
        torch_utils.normalize_angle(torch.tensor([3 * math.pi / 2])), torch.tensor([-math.pi / 2])
    )
    roll, _, _ = torch_utils.get_euler_xyz(math_utils.quat_from_euler_xyz(torch.tensor([-0.5]), torch.zeros(1), yaw))
    torch.testing.assert_close(roll, torch.tensor([2 * math.pi - 0.5]))  # in [0, 2 pi), as Isaac Sim's


def test_they_compile_with_torchscript():
    """Isaac Lab's locomotion env calls them from its own @torch.jit.script function."""
    for function in (compute_heading_and_up, compute_rot, torch_utils.get_euler_xyz, torch_utils.normalize_angle,
                     torch_utils.unscale, torch_utils.scale, torch_utils.tensor_clamp, torch_utils.tf_combine,
                     torch_utils.tf_inverse, torch_utils.tf_apply, torch_utils.tf_vector):  # fmt: skip
        torch.jit.script(function)
