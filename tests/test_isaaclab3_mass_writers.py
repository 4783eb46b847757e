"""Isaac Lab 3.0's mass-property setters and centre-of-mass pose writer on simlab.v3's assets (issue 42.3):
``set_masses`` / ``set_coms`` / ``set_inertias`` (``_index`` and ``_mask``) write each world's MuJoCo
model, ``write_root_com_pose_to_sim_index`` places the root by its centre of mass frame (x, y, z, w)."""

from __future__ import annotations

import pytest
import torch

import simlab.sim as sim_utils
import simlab.utils.math as math2
import simlab.v3.utils.math as math3
from simlab.robots import ANT_CFG, CARTPOLE_CFG
from simlab.utils import configclass
from simlab.v3 import assets as assets3
from simlab.v3 import scene as scene3


@configclass
class _SceneCfg(scene3.InteractiveSceneCfg):
    robot = CARTPOLE_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
    ant = ANT_CFG.replace(prim_path="{ENV_REGEX_NS}/Ant")  # bodies whose inertia frames are their own
    box = assets3.RigidObjectCfg(
        prim_path="{ENV_REGEX_NS}/Box",
        spawn=sim_utils.CuboidCfg(
            size=(0.4, 0.2, 0.1),
            rigid_props=sim_utils.RigidBodyPropertiesCfg(disable_gravity=True),
            mass_props=sim_utils.MassPropertiesCfg(mass=1.0),
        ),
        init_state=assets3.RigidObjectCfg.InitialStateCfg(pos=(0.0, 1.0, 1.0)),
    )


@pytest.fixture
def scene():
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    scene = scene3.InteractiveScene(_SceneCfg(num_envs=3, env_spacing=3.0))
    sim.reset()
    scene.update(sim.get_physics_dt())
    return scene


def test_masses_are_written_per_world_and_masks_select_envs(scene):
    robot = scene["robot"]
    (pole,), _ = robot.find_bodies("pole")
    before = robot.root_physx_view.get_masses()
    robot.set_masses_index(masses=torch.tensor([[2.5]]), body_ids=[pole], env_ids=[1])
    after = robot.root_physx_view.get_masses()
    assert after[1, pole] == 2.5 and torch.equal(after[[0, 2]], before[[0, 2]])
    full = after.clone()
    full[:, pole] = 4.0
    robot.set_masses_mask(masses=full, env_mask=torch.tensor([True, False, False]))
    masses = robot.root_physx_view.get_masses()
    assert masses[0, pole] == 4.0 and masses[1, pole] == 2.5 and masses[2, pole] == before[2, pole]
    with pytest.raises(ValueError, match=r"body_mass: 1 envs x 1 bodies take a tensor of shape \(1, 1\)"):
        robot.set_masses_index(masses=torch.ones(2), body_ids=[pole], env_ids=[1])
    with pytest.raises(TypeError, match="set_masses_index\\(\\): missing \\['masses'\\]"):
        robot.set_masses_index(mass=torch.ones(1, 1))


def test_an_inertia_tensor_round_trips_through_mujocos_principal_axes(scene):
    ant = scene["ant"]
    (leg,), _ = ant.find_bodies("front_left_leg")
    turn = math2.matrix_from_quat(math2.quat_from_euler_xyz(torch.tensor(0.3), torch.tensor(-0.5), torch.tensor(1.2)))
    inertia = turn @ torch.diag(torch.tensor([0.01, 0.02, 0.04])) @ turn.T
    ant.set_inertias_index(inertias=inertia.reshape(1, 1, 9), body_ids=[leg], env_ids=[2])
    read = ant.root_physx_view.get_inertias()
    assert torch.allclose(read[2, leg], inertia.reshape(9), atol=1e-6)
    assert not torch.allclose(read[0, leg], inertia.reshape(9), atol=1e-4)
    box = scene["box"]  # a box's inertia frame is its body frame: turning it is refused, its axes' moments are set
    box.set_inertias_index(inertias=torch.diag(torch.tensor([0.1, 0.2, 0.3])).reshape(1, 1, 9), env_ids=[1])
    assert torch.allclose(
        box.root_physx_view.get_inertias()[1, 0], torch.diag(torch.tensor([0.1, 0.2, 0.3])).reshape(9)
    )
    with pytest.raises(ValueError, match="Box/body: MuJoCo compiled this body with its principal axes of inertia on"):
        box.set_inertias_index(inertias=inertia.reshape(1, 1, 9), env_ids=[1])
    with pytest.raises(ValueError, match="Box/body: MuJoCo compiled this body with its centre of mass on the body"):
        box.set_coms_index(coms=torch.tensor([[[0.05, 0.0, 0.0]]]), env_ids=[1])


def test_the_root_is_placed_by_its_centre_of_mass_frame(scene):
    ant = scene["ant"]
    # a centre of mass off the torso's origin (3.0's pose: x, y, z, w); MuJoCo's principal axes stay turned
    ant.set_coms_index(coms=torch.tensor([[[0.1, -0.05, 0.02]]]), body_ids=[0], env_ids=[0])
    sim = sim_utils.SimulationContext.instance()
    com_quat_b = torch.tensor(sim.model.body_iquat[int(ant._body_ids[0])], dtype=torch.float32)
    target_quat = math3.quat_from_euler_xyz(torch.tensor([0.2]), torch.tensor([0.1]), torch.tensor([-0.7]))
    target_pos = scene.env_origins[0:1] + torch.tensor([[0.3, 0.4, 1.5]])
    ant.write_root_com_pose_to_sim_index(root_pose=torch.cat((target_pos, target_quat), -1), env_ids=[0])
    sim.forward()
    assert torch.allclose(ant.data.body_com_pos_w[0, 0], target_pos[0], atol=1e-5)
    # the centre of mass frame's orientation: the link's, then the principal axes'
    com_quat = math2.quat_mul(ant.data.root_quat_w[0], com_quat_b)
    expected = math3.wxyz_from_xyzw(target_quat[0])
    assert torch.allclose(math2.quat_unique(com_quat), math2.quat_unique(expected), atol=1e-5)
    assert not torch.allclose(ant.data.root_pos_w[0], target_pos[0], atol=1e-3)  # the link is elsewhere


def test_the_mask_writer_places_each_env_by_its_own_centre_of_mass(scene):
    """``write_root_com_pose_to_sim_mask``: full data and a bool mask; each masked env uses its own world's
    centre of mass (a mask read as indices would take env 0's or 1's)."""
    ant = scene["ant"]
    ant.set_coms_index(coms=torch.tensor([[[0.1, -0.05, 0.02]]]), body_ids=[0], env_ids=[2])  # env 2's only
    quat = math3.quat_from_euler_xyz(torch.zeros(3), torch.zeros(3), torch.zeros(3))
    pos = scene.env_origins + torch.tensor([[0.3, 0.4, 1.5]])
    before = ant.data.root_pos_w.clone()
    mask = torch.tensor([False, False, True])
    ant.write_root_com_pose_to_sim_mask(root_pose=torch.cat((pos, quat), -1), env_mask=mask)
    sim_utils.SimulationContext.instance().forward()
    assert torch.allclose(ant.data.body_com_pos_w[2, 0], pos[2], atol=1e-5)
    assert torch.equal(ant.data.root_pos_w[:2], before[:2])  # envs outside the mask keep their pose
