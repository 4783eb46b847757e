"""RigidObjectCollection: several rigid objects with an object axis, on MuJoCo and on MuJoCo Warp.

Oracles: the discrete free fall of MuJoCo's semi-implicit Euler step (v += g dt, then p += v dt);
SciPy's Rotation for the link <-> centre-of-mass frame changes; Newton's second law for a wrench;
the inertia of a uniform box and ball from their formulas.
"""

from __future__ import annotations

import gc
import weakref

import numpy as np
import pytest
import torch
from scipy.spatial.transform import Rotation
from test_engine_choice import needs_warp

import simlab.sim as sim_utils
from simlab.assets import RigidObjectCfg, RigidObjectCollection, RigidObjectCollectionCfg
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.utils import configclass

DT = 0.01
NUM_ENVS = 3
COM_OFFSET = (0.1, -0.05, 0.02)
"""Where the centre of mass of the offset block sits in its link frame [m]."""

OFFSET_BLOCK_XML = f"""
<mujoco>
  <worldbody>
    <body name="block">
      <freejoint/>
      <geom type="box" size="0.1 0.1 0.1" mass="0"/>
      <inertial pos="{" ".join(map(str, COM_OFFSET))}" quat="0.9238795 0 0.3826834 0" mass="1.5"
                diaginertia="0.01 0.02 0.03"/>
    </body>
  </worldbody>
</mujoco>
"""


def free(spawn, prim_path: str, pos: tuple[float, float, float]) -> RigidObjectCfg:
    return RigidObjectCfg(prim_path=prim_path, spawn=spawn, init_state=RigidObjectCfg.InitialStateCfg(pos=pos))


def scene_cfg(block_xml: str) -> InteractiveSceneCfg:
    rigid = sim_utils.RigidBodyPropertiesCfg()

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        objects = RigidObjectCollectionCfg(
            rigid_objects={
                "cube": free(
                    sim_utils.CuboidCfg(
                        size=(0.2, 0.2, 0.2), rigid_props=rigid, mass_props=sim_utils.MassPropertiesCfg(mass=2.0)
                    ),
                    "{ENV_REGEX_NS}/Cube",
                    (0.0, 0.0, 5.0),
                ),
                "ball": free(
                    sim_utils.SphereCfg(
                        radius=0.1, rigid_props=rigid, mass_props=sim_utils.MassPropertiesCfg(mass=1.0)
                    ),
                    "{ENV_REGEX_NS}/Ball",
                    (1.0, 0.0, 5.0),
                ),
                "block": free(sim_utils.MjcfFileCfg(asset_path=block_xml), "{ENV_REGEX_NS}/Block", (2.0, 0.0, 5.0)),
            }
        )

    return SceneCfg(num_envs=NUM_ENVS, env_spacing=4.0)


@pytest.fixture(params=["mujoco", pytest.param("mujoco_warp", marks=needs_warp)])
def collection(request, tmp_path):
    xml = tmp_path / "block.xml"
    xml.write_text(OFFSET_BLOCK_XML)
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=DT, device="cpu", engine=request.param))
    scene = InteractiveScene(scene_cfg(str(xml)))
    sim.reset()
    yield sim, scene, scene["objects"]
    sim_utils.SimulationContext.clear_instance()


def run(sim, scene, steps: int) -> None:
    for _ in range(steps):
        scene.write_data_to_sim()
        sim.step()
        scene.update(DT)


def test_shapes_names_and_defaults(collection):
    _, scene, objects = collection
    data = objects.data
    assert objects.num_objects == 3 and objects.object_names == ["cube", "ball", "block"]
    assert objects.find_objects(["ba.*", "cube"], preserve_order=True) == ([1, 0], ["ball", "cube"])
    for name, width in (
        ("object_state_w", 13),
        ("object_link_pose_w", 7),
        ("object_com_vel_w", 6),
        ("projected_gravity_b", 3),
    ):
        assert getattr(data, name).shape == (NUM_ENVS, 3, width), name
    assert data.heading_w.shape == (NUM_ENVS, 3)
    torch.testing.assert_close(data.default_mass[0, :, 0], torch.tensor([2.0, 1.0, 1.5]))
    # uniform box m (a^2 + a^2) / 12, ball 2/5 m r^2; the block's tensor is R diag R^T about its principal axes
    rot = Rotation.from_quat([0.0, 0.3826834, 0.0, 0.9238795]).as_matrix()
    expected = [np.eye(3) * 2.0 * 0.08 / 12, np.eye(3) * 0.4 * 0.01, rot @ np.diag([0.01, 0.02, 0.03]) @ rot.T]
    np.testing.assert_allclose(data.default_inertia[1].numpy(), np.stack(expected).reshape(3, 9), atol=1e-6)
    # the initial positions are the configs', in each env's frame
    torch.testing.assert_close(data.object_link_pos_w - scene.env_origins[:, None], data.default_object_state[..., :3])
    # Isaac Lab 3.0 calls the objects bodies: same quantities under its names
    assert objects.num_bodies == 3 and objects.body_names == objects.object_names
    assert objects.find_bodies("block") == ([2], ["block"])
    torch.testing.assert_close(data.body_link_pose_w, data.object_link_pose_w)
    torch.testing.assert_close(data.body_com_vel_w, data.object_com_vel_w)
    torch.testing.assert_close(data.default_body_pose, data.default_object_state[..., :7])
    torch.testing.assert_close(data.body_mass, data.default_mass[..., 0])


def test_free_fall_matches_the_discrete_integrator(collection):
    sim, scene, objects = collection
    data = objects.data
    state = data.default_object_state.clone()
    state[..., :3] += scene.env_origins[:, None]
    v0 = torch.tensor([0.5, -0.2, 1.0])
    state[..., 7:10] = v0
    objects.write_object_state_to_sim(state)
    start = data.object_com_pos_w.clone()
    steps, g = 20, torch.tensor([0.0, 0.0, -9.81])
    run(sim, scene, steps)
    # v_k = v0 + k g dt; p_N = p0 + N v0 dt + g dt^2 N (N + 1) / 2
    expected = start + steps * DT * v0 + g * DT**2 * steps * (steps + 1) / 2
    torch.testing.assert_close(data.object_com_pos_w, expected, atol=1e-4, rtol=0)
    torch.testing.assert_close(
        data.object_com_lin_vel_w, (v0 + steps * DT * g).expand(NUM_ENVS, 3, 3), atol=1e-4, rtol=0
    )


def test_com_frame_writes_and_reads_match_scipy(collection):
    _, _, objects = collection
    data = objects.data
    rng = np.random.default_rng(0)
    rot = Rotation.random(NUM_ENVS, random_state=rng)
    com_pos = rng.uniform(-1, 1, (NUM_ENVS, 3)) + [0, 0, 5]
    pose = torch.tensor(np.concatenate([com_pos, np.roll(rot.as_quat(), 1, axis=-1)], -1), dtype=torch.float32)
    objects.write_object_com_pose_to_sim(pose[:, None], object_ids=[2])
    principal = Rotation.from_quat([0.0, 0.3826834, 0.0, 0.9238795])
    link_rot = rot * principal.inv()  # the link frame that puts the principal axes at rot
    link_pos = com_pos - link_rot.apply(COM_OFFSET)
    np.testing.assert_allclose(data.object_link_pos_w[:, 2].numpy(), link_pos, atol=1e-5)
    got = Rotation.from_quat(np.roll(data.object_link_quat_w[:, 2].numpy(), -1, axis=-1))
    assert (got * link_rot.inv()).magnitude().max() < 1e-5
    np.testing.assert_allclose(data.object_com_pose_w[:, 2].numpy(), pose.numpy(), atol=1e-5)
    objects.write_body_com_pose_to_sim(pose[:, None], body_ids=[0])  # Isaac Lab 3.0's name, another object
    np.testing.assert_allclose(data.body_com_pose_w[:, 0].numpy(), pose.numpy(), atol=1e-5)

    lin, ang = rng.uniform(-1, 1, (NUM_ENVS, 3)), rng.uniform(-3, 3, (NUM_ENVS, 3))
    velocity = torch.tensor(np.concatenate([lin, ang], -1), dtype=torch.float32)
    objects.write_object_com_velocity_to_sim(velocity[:, None], object_ids=[2])
    np.testing.assert_allclose(data.object_com_vel_w[:, 2].numpy(), velocity.numpy(), atol=1e-5)
    # the link origin moves at v_com + w x (link - com)
    link_lin = lin + np.cross(ang, link_pos - com_pos)
    np.testing.assert_allclose(data.object_link_lin_vel_w[:, 2].numpy(), link_lin, atol=1e-5)
    np.testing.assert_allclose(
        data.object_com_lin_vel_b[:, 2].numpy(), link_rot.inv().apply(lin), atol=1e-5
    )  # body frame = link frame


def test_writes_touch_only_the_selected_envs_and_objects(collection):
    _, _, objects = collection
    data = objects.data
    before = data.object_link_state_w.clone()
    pose = torch.tensor([[[9.0, 8.0, 7.0, 0.0, 1.0, 0.0, 0.0]], [[-9.0, -8.0, 7.0, 0.0, 0.0, 1.0, 0.0]]])
    objects.write_object_link_pose_to_sim(pose, env_ids=torch.tensor([2, 0]), object_ids=[1])
    after = data.object_link_state_w
    torch.testing.assert_close(after[2, 1, :7], pose[0, 0])
    torch.testing.assert_close(after[0, 1, :7], pose[1, 0])
    changed = torch.zeros(NUM_ENVS, 3, dtype=torch.bool)
    changed[[2, 0], 1] = True
    torch.testing.assert_close(after[~changed], before[~changed])
    # a bool env mask takes values for every env and writes the masked rows only
    velocity = torch.arange(NUM_ENVS * 3 * 6, dtype=torch.float32).reshape(NUM_ENVS, 3, 6) / 10
    mask = torch.tensor([False, True, False])
    objects.write_object_link_velocity_to_sim(velocity, env_ids=mask)
    torch.testing.assert_close(data.object_link_vel_w[1], velocity[1], atol=1e-5, rtol=0)
    torch.testing.assert_close(data.object_link_vel_w[[0, 2]], before[[0, 2], :, 7:])
    # values that broadcast, as Isaac Lab's writers take them: one env's (objects, 7) (its stack event's)
    poses = torch.tensor([[1.0, 2.0, 3.0, 1.0, 0.0, 0.0, 0.0], [4.0, 5.0, 6.0, 1.0, 0.0, 0.0, 0.0]])
    objects.write_object_link_pose_to_sim(poses, env_ids=torch.tensor([1]), object_ids=[0, 2])
    torch.testing.assert_close(data.object_link_state_w[1, [0, 2], :7], poses)


def test_wrench_on_one_object_of_one_env(collection):
    sim, scene, objects = collection
    data = objects.data
    force = torch.zeros(1, 1, 3)
    force[..., 2] = 30.0  # on the 2 kg cube: a = 15 - 9.81 up
    objects.set_external_force_and_torque(force, torch.zeros(1, 1, 3), object_ids=[0], env_ids=torch.tensor([1]))
    run(sim, scene, 10)
    vz = data.object_com_lin_vel_w[..., 2]
    expected = torch.full((NUM_ENVS, 3), -9.81 * 10 * DT)
    expected[1, 0] = (30.0 / 2.0 - 9.81) * 10 * DT
    torch.testing.assert_close(vz, expected, atol=1e-4, rtol=0)
    objects.reset(env_ids=torch.tensor([1]), object_ids=[0])  # the force stops
    run(sim, scene, 10)
    expected[1, 0] -= 9.81 * 10 * DT
    expected[[0, 2]] -= 9.81 * 10 * DT
    expected[1, 1:] -= 9.81 * 10 * DT
    torch.testing.assert_close(data.object_com_lin_vel_w[..., 2], expected, atol=1e-4, rtol=0)


def test_errors_say_what_was_wrong(collection):
    _, _, objects = collection
    with pytest.raises(ValueError, match=r"object_pose must have shape \(3, 2, 7\)"):
        objects.write_object_pose_to_sim(torch.zeros(3, 3, 7), object_ids=[0, 1])
    with pytest.raises(IndexError, match=r"object_ids \[5\] out of range.*\['cube', 'ball', 'block'\]"):
        objects.write_object_velocity_to_sim(torch.zeros(3, 1, 6), object_ids=[5])
    with pytest.raises(AttributeError, match="collection.data.default_mass"):
        objects.root_physx_view.get_masses()
    with pytest.raises(ValueError, match="rigid_objects is empty"):
        RigidObjectCollection(RigidObjectCollectionCfg(rigid_objects={}))
    # Isaac Lab's flat (env, object) index: objects major
    ids = objects._env_obj_ids_to_view_ids(torch.tensor([0, 2]), torch.tensor([1, 2]))
    assert ids.tolist() == [1 * 3 + 0, 2 * 3 + 0, 1 * 3 + 2, 2 * 3 + 2]


def test_the_simulation_does_not_keep_a_collection_alive(tmp_path):
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=DT, device="cpu"))
    ball = sim_utils.SphereCfg(radius=0.1, rigid_props=sim_utils.RigidBodyPropertiesCfg())
    collection = RigidObjectCollection(
        RigidObjectCollectionCfg(rigid_objects={"a": free(ball, "/World/A", (0.0, 0.0, 1.0))})
    )
    alive = weakref.ref(collection)
    del collection
    gc.collect()
    assert alive() is None
    sim.reset()  # its objects still bind
    sim_utils.SimulationContext.clear_instance()
