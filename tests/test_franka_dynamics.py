"""The Franka model, and the Jacobians / mass matrices / gravity forces simlab computes from the physics.

Values are checked against MuJoCo itself (mj_jacBody, mj_fullM, qfrc_bias) and against finite
differences of the forward kinematics, on every backend.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
import torch
from conftest import DEVICES

import simlab.sim as sim_utils
from simlab.assets import ArticulationCfg, AssetBaseCfg
from simlab.robots.franka import FRANKA_PANDA_CFG, FRANKA_PANDA_HIGH_PD_CFG
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.utils import configclass

ARM_JOINTS = [f"panda_joint{i}" for i in range(1, 8)]


@configclass
class FrankaSceneCfg(InteractiveSceneCfg):
    ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
    robot: ArticulationCfg = FRANKA_PANDA_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")


def make_scene(device: str, num_envs: int = 3, robot_cfg=None, dt: float = 0.01, **scene_fields):
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=dt, device=device))
    cfg = FrankaSceneCfg(num_envs=num_envs, env_spacing=2.0)
    if robot_cfg is not None:
        cfg.robot = robot_cfg.replace(prim_path="{ENV_REGEX_NS}/Robot")
    for name, value in scene_fields.items():
        setattr(cfg, name, value)
    scene = InteractiveScene(cfg)
    sim.reset()
    return sim, scene


def step(sim, scene, n: int = 1):
    for _ in range(n):
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())


def random_arm_pose(robot, generator: torch.Generator) -> torch.Tensor:
    low, high = robot.data.soft_joint_pos_limits[..., 0], robot.data.soft_joint_pos_limits[..., 1]
    u = torch.rand(low.shape, generator=generator).to(low.device)
    return low + (high - low) * (0.1 + 0.8 * u)


def test_franka_has_isaac_lab_names_groups_and_default_pose():
    sim, scene = make_scene("cpu", num_envs=1)
    robot = scene["robot"]
    assert robot.joint_names == ARM_JOINTS + ["panda_finger_joint1", "panda_finger_joint2"]
    assert robot.body_names == [f"panda_link{i}" for i in range(8)] + [
        "panda_hand",
        "panda_leftfinger",
        "panda_rightfinger",
    ]
    assert set(robot.actuators) == {"panda_shoulder", "panda_forearm", "panda_hand"}
    assert robot.is_fixed_base
    torch.testing.assert_close(robot.data.joint_stiffness[0], torch.tensor([80.0] * 7 + [2000.0] * 2))
    torch.testing.assert_close(robot.data.joint_effort_limits[0], torch.tensor([87.0] * 4 + [12.0] * 3 + [200.0] * 2))
    # Franka's published kinematics: with all joints at zero the flange is at (0.088, 0, 0.926).
    robot.write_joint_state_to_sim(torch.zeros(1, 9), torch.zeros(1, 9))
    hand = robot.find_bodies("panda_hand")[0][0]
    torch.testing.assert_close(robot.data.body_pos_w[0, hand] - scene.env_origins[0], torch.tensor([0.088, 0.0, 0.926]))


def test_franka_sags_under_gravity_until_its_pd_torque_holds_the_weight():
    """kp 80 holds the arm where kp (q* - q) equals the torque gravity needs (as PhysX's drive would)."""
    sim, scene = make_scene("cpu", num_envs=1, dt=1.0 / 60.0)
    robot = scene["robot"]
    robot.set_joint_position_target(robot.data.default_joint_pos)
    step(sim, scene, 400)
    assert robot.data.joint_vel.abs().max() < 1e-3
    pd_torque = robot.data.joint_stiffness * (robot.data.default_joint_pos - robot.data.joint_pos)
    gravity = robot.root_physx_view.get_gravity_compensation_forces()
    torch.testing.assert_close(pd_torque, gravity, atol=0.05, rtol=0.01)
    assert gravity[0, 1].abs() > 5.0  # the shoulder does carry weight


def test_high_pd_franka_ignores_gravity():
    sim, scene = make_scene("cpu", num_envs=1, robot_cfg=FRANKA_PANDA_HIGH_PD_CFG, dt=1.0 / 60.0)
    robot = scene["robot"]
    robot.set_joint_position_target(robot.data.default_joint_pos)
    step(sim, scene, 60)
    assert (robot.data.joint_pos - robot.data.default_joint_pos).abs().max() < 1e-3
    gravity = robot.root_physx_view.get_gravity_compensation_forces()
    assert gravity.abs().max() == 0.0


@pytest.mark.parametrize("device", DEVICES)
def test_jacobian_matches_finite_differences(device):
    sim, scene = make_scene(device, num_envs=3)
    robot = scene["robot"]
    gen = torch.Generator().manual_seed(0)
    q = random_arm_pose(robot, gen)
    robot.write_joint_state_to_sim(q, torch.zeros_like(q))
    jac = robot.root_physx_view.get_jacobians()
    assert jac.shape == (3, robot.num_bodies - 1, 6, robot.num_joints)
    hand = robot.find_bodies("panda_hand")[0][0]
    eps = 1e-3
    pos0, quat0 = robot.data.body_pos_w[:, hand].clone(), robot.data.body_quat_w[:, hand].clone()
    for j in range(robot.num_joints):
        dq = torch.zeros_like(q)
        dq[:, j] = eps
        robot.write_joint_position_to_sim(q + dq)
        pos1, quat1 = robot.data.body_pos_w[:, hand], robot.data.body_quat_w[:, hand]
        lin = (pos1 - pos0) / eps
        from simlab.utils.math import axis_angle_from_quat, quat_conjugate, quat_mul

        ang = axis_angle_from_quat(quat_mul(quat1, quat_conjugate(quat0))) / eps
        torch.testing.assert_close(jac[:, hand - 1, :3, j], lin, atol=2e-3, rtol=0)
        torch.testing.assert_close(jac[:, hand - 1, 3:, j], ang, atol=2e-3, rtol=0)


def test_jacobian_mass_matrix_and_bias_match_mujoco():
    sim, scene = make_scene("cpu", num_envs=2)
    robot = scene["robot"]
    gen = torch.Generator().manual_seed(1)
    q = random_arm_pose(robot, gen)
    qd = torch.randn(q.shape, generator=gen)
    robot.write_joint_state_to_sim(q, qd)
    view = robot.root_physx_view
    jac, mass = view.get_jacobians(), view.get_generalized_mass_matrices()
    gravity, coriolis = view.get_gravity_compensation_forces(), view.get_coriolis_and_centrifugal_compensation_forces()

    model = sim.model
    data = mujoco.MjData(model)
    for env in range(2):
        data.qpos[:] = model.qpos0
        data.qpos[:9] = q[env].double().numpy()
        data.qvel[:9] = qd[env].double().numpy()
        mujoco.mj_forward(model, data)
        full = np.zeros((model.nv, model.nv))
        mujoco.mj_fullM(model, data, full)
        np.testing.assert_allclose(mass[env].numpy(), full[:9, :9], atol=1e-4, rtol=1e-4)
        for k, body in enumerate(robot.body_names[1:]):
            jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
            mujoco.mj_jacBody(model, data, jacp, jacr, model.body("Robot/" + body).id)
            np.testing.assert_allclose(jac[env, k, :3].numpy(), jacp[:, :9], atol=1e-5)
            np.testing.assert_allclose(jac[env, k, 3:].numpy(), jacr[:, :9], atol=1e-5)
        np.testing.assert_allclose((gravity + coriolis)[env].numpy(), data.qfrc_bias[:9], atol=1e-3, rtol=1e-4)
        # gravity alone: MuJoCo's bias at zero velocity
        data.qvel[:] = 0
        mujoco.mj_forward(model, data)
        np.testing.assert_allclose(gravity[env].numpy(), data.qfrc_bias[:9], atol=1e-3, rtol=1e-4)


def test_floating_base_jacobian_uses_world_frame_root_dofs():
    """A floating root: PhysX's first 6 dofs are the root's world-frame linear and angular velocity."""
    sim, scene = make_scene(
        "cpu",
        num_envs=1,
        robot_cfg=FRANKA_PANDA_CFG.replace(
            spawn=FRANKA_PANDA_CFG.spawn.replace(asset_path=_floating_franka()),
        ),
    )
    robot = scene["robot"]
    assert not robot.is_fixed_base
    root_state = robot.data.default_root_state.clone()
    root_state[:, 3:7] = torch.tensor([[0.9, 0.3, -0.2, 0.25]])
    robot.write_root_state_to_sim(root_state)
    view = robot.root_physx_view
    jac = view.get_jacobians()
    assert jac.shape == (1, robot.num_bodies, 6, robot.num_joints + 6)
    # a world-frame root angular velocity w turns every body at w
    hand = robot.find_bodies("panda_hand")[0][0]
    w = torch.tensor([0.3, -0.2, 0.5])
    torch.testing.assert_close(jac[0, hand, 3:, 3:6] @ w, w, atol=1e-5, rtol=0)
    # the root's own linear velocity is the root linear-velocity dofs
    torch.testing.assert_close(jac[0, 0, :3, 0:3], torch.eye(3), atol=1e-6, rtol=0)
    mass = view.get_generalized_mass_matrices()
    armature = torch.tensor(sim.model.dof_armature[:3], dtype=torch.float32)
    expected = torch.eye(3) * float(robot.data.default_mass.sum()) + torch.diag(armature)
    torch.testing.assert_close(mass[0, :3, :3], expected, atol=1e-4, rtol=1e-4)
    torch.testing.assert_close(mass, mass.transpose(-1, -2), atol=1e-5, rtol=0)


def _floating_franka() -> str:
    import os
    import tempfile

    from simlab.robots.franka import ASSETS_DIR

    spec = mujoco.MjSpec.from_file(os.path.join(ASSETS_DIR, "franka_panda.xml"))
    spec.worldbody.bodies[0].add_freejoint()
    path = os.path.join(tempfile.mkdtemp(), "floating_franka.xml")
    with open(path, "w") as f:
        f.write(spec.to_xml())
    return path
