"""External wrenches (Isaac Lab's WrenchComposer) and the bodies' masses under PhysX's view names.

Oracles: SciPy's Rotation for the frame changes, NumPy's cross product for lever arms, Newton's
second law (dv = F dt / m) for what the simulation does with the composed wrench.
"""

from __future__ import annotations

import numpy as np
import pytest
import torch
from scipy.spatial.transform import Rotation
from test_scene_articulation import CartpoleSceneCfg, CubeSceneCfg, make_scene, step

from simlab.utils.wrench_composer import WrenchComposer


class FakeAsset:
    """What a composer reads from an asset: sizes, device and the bodies' link poses."""

    def __init__(self, num_envs: int, num_bodies: int, pos: np.ndarray, quat_wxyz: np.ndarray):
        self.num_instances, self.num_bodies, self.device = num_envs, num_bodies, "cpu"
        self.data = type("Data", (), {})()
        self.data.body_link_pos_w = torch.tensor(pos, dtype=torch.float32)
        self.data.body_link_quat_w = torch.tensor(quat_wxyz, dtype=torch.float32)


def random_asset(rng, num_envs=5, num_bodies=3):
    rot = Rotation.random(num_envs * num_bodies, random_state=rng)
    quat = np.roll(rot.as_quat(), 1, axis=-1).reshape(num_envs, num_bodies, 4)  # SciPy is (x, y, z, w)
    pos = rng.uniform(-2, 2, (num_envs, num_bodies, 3))
    return FakeAsset(num_envs, num_bodies, pos, quat), rot


def test_added_wrenches_sum_on_the_selected_envs_and_bodies():
    rng = np.random.default_rng(0)
    asset, _ = random_asset(rng)
    composer = WrenchComposer(asset)
    assert not composer.active
    expected_f, expected_t = np.zeros((5, 3, 3)), np.zeros((5, 3, 3))
    for _ in range(6):
        envs = rng.choice(5, size=rng.integers(1, 6), replace=False)
        bodies = rng.choice(3, size=rng.integers(1, 4), replace=False)
        f = rng.uniform(-10, 10, (len(envs), len(bodies), 3))
        t = rng.uniform(-10, 10, (len(envs), len(bodies), 3))
        composer.add_forces_and_torques(torch.tensor(f), torch.tensor(t), body_ids=bodies.tolist(),
                                        env_ids=torch.tensor(envs))  # fmt: skip
        expected_f[envs[:, None], bodies[None, :]] += f
        expected_t[envs[:, None], bodies[None, :]] += t
    assert composer.active
    np.testing.assert_allclose(composer.composed_force.numpy(), expected_f, atol=1e-4)
    np.testing.assert_allclose(composer.composed_torque.numpy(), expected_t, atol=1e-4)
    composer.reset(torch.tensor([1, 3]))
    expected_f[[1, 3]] = 0.0
    np.testing.assert_allclose(composer.composed_force.numpy(), expected_f, atol=1e-4)
    assert composer.active
    composer.reset()
    assert not composer.active and not composer.composed_torque.any()


def test_global_wrenches_at_world_points_are_rotated_into_the_link_frame():
    rng = np.random.default_rng(1)
    asset, rot = random_asset(rng)
    composer = WrenchComposer(asset)
    f_w, t_w = rng.uniform(-10, 10, (2, 5, 3, 3))
    point_w = rng.uniform(-3, 3, (5, 3, 3))
    composer.add_forces_and_torques(torch.tensor(f_w), torch.tensor(t_w), torch.tensor(point_w), is_global=True)
    inv = rot.inv()
    f_b = inv.apply(f_w.reshape(-1, 3))
    arm_b = inv.apply((point_w - asset.data.body_link_pos_w.numpy()).reshape(-1, 3))
    t_b = inv.apply(t_w.reshape(-1, 3)) + np.cross(arm_b, f_b)  # torque about the link origin, link frame
    np.testing.assert_allclose(composer.composed_force.numpy().reshape(-1, 3), f_b, atol=1e-4)
    np.testing.assert_allclose(composer.composed_torque.numpy().reshape(-1, 3), t_b, atol=1e-3)


def test_set_replaces_and_a_mask_keeps_the_other_rows():
    rng = np.random.default_rng(2)
    asset, _ = random_asset(rng, num_envs=4, num_bodies=2)
    composer = WrenchComposer(asset)
    ones = torch.ones(4, 2, 3)
    composer.add_forces_and_torques(forces=ones, torques=ones)
    arm = torch.zeros(4, 1, 3)
    arm[..., 1] = 0.5  # 0.5 m along the link's y axis
    force = torch.zeros(4, 1, 3)
    force[..., 0] = 2.0  # 2 N along x: a torque of -1 N m about z
    mask = torch.tensor([True, False, True, False])
    composer.set_forces_and_torques(forces=force, positions=arm, body_ids=[1], env_ids=mask)
    assert composer.composed_force[:, 1, 0].tolist() == [2.0, 1.0, 2.0, 1.0]
    assert composer.composed_torque[:, 1].tolist() == [[0, 0, -1.0], [1, 1, 1], [0, 0, -1.0], [1, 1, 1]]
    assert (composer.composed_force[:, 0] == 1.0).all(), "body 0 untouched"
    with pytest.raises(ValueError, match=r"forces must have shape \(2, 1, 3\)"):
        composer.set_forces_and_torques(forces=torch.zeros(3, 1, 3), body_ids=[0], env_ids=[0, 1])


def test_permanent_wrench_keeps_pushing_and_instantaneous_pushes_once():
    dt = 0.002
    sim, scene = make_scene(CubeSceneCfg(num_envs=2, env_spacing=2.0), "cpu", dt=dt, gravity=(0.0, 0.0, 0.0))
    cube = scene["cube"]  # 2 kg
    push = torch.tensor([[[4.0, 0.0, 0.0]], [[0.0, 0.0, 0.0]]])
    cube.permanent_wrench_composer.set_forces_and_torques(forces=push, is_global=True)
    cube.instantaneous_wrench_composer.add_forces_and_torques(forces=push.roll(1, 0) * 10, is_global=True)
    step(sim, scene, 50)
    vel = cube.data.root_lin_vel_w[:, 0]
    # env 0: 4 N for 0.1 s -> 0.2 m/s; env 1: 40 N for one step only -> 40 / 2 * dt
    assert vel.tolist() == pytest.approx([4.0 / 2.0 * 50 * dt, 40.0 / 2.0 * dt], abs=1e-5)
    assert not cube.instantaneous_wrench_composer.active
    cube.reset()  # a reset clears the wrenches: the cube coasts
    assert not cube.permanent_wrench_composer.active
    step(sim, scene, 10)
    assert cube.data.root_lin_vel_w[:, 0].tolist() == pytest.approx(vel.tolist(), abs=1e-6)


def test_body_masses_under_physx_view_names():
    sim, scene = make_scene(CartpoleSceneCfg(num_envs=3, env_spacing=2.0), "cpu")
    robot, model = scene["cartpole"], sim.model
    view = robot.root_physx_view
    masses = view.get_masses()
    expected = [model.body(f"{robot.prefix}{name}").mass[0] for name in robot.body_names]
    assert masses.device.type == "cpu" and masses.shape == (3, robot.num_bodies)
    np.testing.assert_allclose(masses.numpy(), np.tile(expected, (3, 1)), rtol=1e-6)
    heavier = masses.clone()
    heavier[1] *= 2.0
    view.set_masses(heavier, torch.tensor([1]))
    np.testing.assert_allclose(view.get_masses().numpy(), heavier.numpy(), rtol=1e-6)
    np.testing.assert_allclose(robot.data.body_mass.numpy(), heavier.numpy(), rtol=1e-6)
    # inertia tensors in the body frame: R diag(I) R^T with MuJoCo's principal axes
    inertias = view.get_inertias().reshape(3, -1, 3, 3).numpy()
    for i, name in enumerate(robot.body_names):
        body = model.body(f"{robot.prefix}{name}")
        axes = Rotation.from_quat(np.roll(body.iquat, -1)).as_matrix()
        np.testing.assert_allclose(inertias[0, i], axes @ np.diag(body.inertia) @ axes.T, atol=1e-6)
    with pytest.raises(AttributeError, match="get_masses, set_masses and get_inertias"):
        view.get_coms()
    with pytest.raises(ValueError, match="a row per env"):
        view.set_masses(heavier[:2], torch.tensor([1]))
