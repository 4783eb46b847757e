"""Simulation, scene, articulations, rigid objects and actuators, on every available backend."""

from __future__ import annotations

import math

import mujoco
import pytest
import torch
from conftest import DEVICES

import simlab.sim as sim_utils
import simlab.utils.math as math_utils
from simlab.actuators import DCMotorCfg, IdealPDActuatorCfg, ImplicitActuatorCfg
from simlab.assets import ArticulationCfg, AssetBaseCfg, RigidObjectCfg
from simlab.robots.cartpole import CARTPOLE_CFG
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.utils import configclass


@configclass
class CartpoleSceneCfg(InteractiveSceneCfg):
    ground = AssetBaseCfg(prim_path="/World/defaultGroundPlane", spawn=sim_utils.GroundPlaneCfg())
    light = AssetBaseCfg(prim_path="/World/Light", spawn=sim_utils.DomeLightCfg(intensity=2000.0))
    cartpole: ArticulationCfg = CARTPOLE_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")


@configclass
class CubeSceneCfg(InteractiveSceneCfg):
    ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
    cube = RigidObjectCfg(
        prim_path="{ENV_REGEX_NS}/Cube",
        spawn=sim_utils.CuboidCfg(
            size=(0.2, 0.2, 0.2),
            rigid_props=sim_utils.RigidBodyPropertiesCfg(),
            mass_props=sim_utils.MassPropertiesCfg(mass=2.0),
        ),
        init_state=RigidObjectCfg.InitialStateCfg(pos=(0.0, 0.0, 1.0)),
    )


def make_scene(scene_cfg, device: str, dt: float = 0.01, **sim_kwargs):
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=dt, device=device, **sim_kwargs))
    scene = InteractiveScene(scene_cfg)
    sim.reset()
    return sim, scene


def step(sim, scene, n: int = 1):
    for _ in range(n):
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())


def test_simulation_cfg_reaches_the_model():
    cfg = sim_utils.SimulationCfg(dt=0.005, gravity=(0.0, 0.0, -3.0), device="cpu")
    cfg.mujoco.integrator = "rk4"
    cfg.mujoco.iterations = 7
    sim, _ = make_scene(CartpoleSceneCfg(num_envs=2, env_spacing=1.0), "cpu", dt=0.005, gravity=(0, 0, -3.0))
    assert sim.get_physics_dt() == 0.005
    assert sim.model.opt.timestep == pytest.approx(0.005)
    assert sim.model.opt.gravity[2] == pytest.approx(-3.0)
    sim_utils.SimulationContext.clear_instance()
    sim = sim_utils.SimulationContext(cfg)
    model = sim.spec.compile()
    assert model.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4 and model.opt.iterations == 7


def test_bad_simulation_options_are_named():
    with pytest.raises(ValueError, match="integrator 'verlet'.*allowed"):
        cfg = sim_utils.SimulationCfg(device="cpu")
        cfg.mujoco.integrator = "verlet"
        sim_utils.SimulationContext(cfg)
    with pytest.raises(ValueError, match="Invalid device 'gpu'"):
        sim_utils.SimulationContext(sim_utils.SimulationCfg(device="gpu"))


@pytest.mark.parametrize("device", DEVICES)
def test_scene_entities_and_origins(device):
    sim, scene = make_scene(CartpoleSceneCfg(num_envs=6, env_spacing=3.0), device)
    assert scene.num_envs == 6 and scene.env_origins.shape == (6, 3)
    assert set(scene.keys()) == {"cartpole", "ground", "light"}
    # origins lie on a grid `env_spacing` apart, centred on zero, in the ground plane
    origins = scene.env_origins.cpu()
    assert torch.all(origins[:, 2] == 0)
    dists = torch.cdist(origins, origins) + torch.eye(6) * 100
    assert dists.min().item() == pytest.approx(3.0)
    assert origins.mean(0).abs().max() < 3.0
    with pytest.raises(KeyError, match="cartpol.*cartpole"):
        scene["cartpol"]


@pytest.mark.parametrize("device", DEVICES)
def test_cartpole_names_defaults_and_root_state(device):
    sim, scene = make_scene(CartpoleSceneCfg(num_envs=4, env_spacing=2.0), device)
    robot = scene["cartpole"]
    assert robot.joint_names == ["slider_to_cart", "cart_to_pole"]
    assert robot.body_names == ["slider", "cart", "pole"]
    assert robot.is_fixed_base and robot.num_instances == 4
    # Spawned 2 m up; world-frame root state includes the env origins.
    state = robot.data.root_state_w
    assert state.shape == (4, 13)
    torch.testing.assert_close(state[:, :3], scene.env_origins + torch.tensor([0.0, 0.0, 2.0], device=sim.device))
    torch.testing.assert_close(
        robot.data.default_root_state[:, :3], torch.tensor([[0.0, 0.0, 2.0]] * 4, device=sim.device)
    )
    # Cartpole facts: 1 kg cart and pole, slider range +-4 m, damping 10, effort limit 400.
    torch.testing.assert_close(robot.data.default_mass[0, 1:], torch.tensor([1.0, 1.0], device=sim.device))
    assert robot.data.joint_pos_limits[0, 0].tolist() == [-4.0, 4.0]
    assert robot.data.joint_damping[0].tolist() == [10.0, 0.0]
    assert robot.data.joint_effort_limits[0].tolist() == [400.0, 400.0]


def test_find_joints_and_bodies():
    _, scene = make_scene(CartpoleSceneCfg(num_envs=1, env_spacing=2.0), "cpu")
    robot = scene["cartpole"]
    assert robot.find_joints("cart_to_pole") == ([1], ["cart_to_pole"])
    assert robot.find_joints(".*_to_.*") == ([0, 1], ["slider_to_cart", "cart_to_pole"])
    assert robot.find_bodies(["pole", "cart"], preserve_order=True) == ([2, 1], ["pole", "cart"])
    with pytest.raises(ValueError, match="(?s)wheel.*slider_to_cart"):
        robot.find_joints("wheel")
    with pytest.raises(ValueError, match="(?s)torso.*slider"):
        robot.find_bodies("torso")


@pytest.mark.parametrize("device", DEVICES)
def test_root_pose_write_moves_fixed_base(device):
    sim, scene = make_scene(CartpoleSceneCfg(num_envs=3, env_spacing=2.0), device)
    robot = scene["cartpole"]
    pose = robot.data.root_state_w[:, :7].clone()
    pose[1, 2] += 0.5  # lift env 1 only
    robot.write_root_pose_to_sim(pose[1:2], env_ids=torch.tensor([1], device=sim.device))
    step(sim, scene)
    z = robot.data.body_pos_w[:, 0, 2].cpu()
    assert z.tolist() == pytest.approx([2.0, 2.5, 2.0], abs=1e-5)
    with pytest.raises(ValueError, match=r"root_pose must have shape \(1, 7\)"):
        robot.write_root_pose_to_sim(pose[:, :3][:1], env_ids=[0])


@pytest.mark.parametrize("device", DEVICES)
def test_joint_state_write_and_selected_reset(device):
    sim, scene = make_scene(CartpoleSceneCfg(num_envs=4, env_spacing=2.0), device)
    robot = scene["cartpole"]
    pos = torch.tensor([[0.5, 0.2]] * 4, device=sim.device)
    robot.write_joint_state_to_sim(pos, torch.zeros_like(pos))
    sim.forward()
    torch.testing.assert_close(robot.data.joint_pos, pos)
    # pole body at 0.2 rad about +x: the pole tips towards -y (Isaac Lab's sign convention)
    sim.physics.reset(torch.tensor([0, 2], device=sim.device))
    jp = robot.data.joint_pos.cpu()
    assert jp[0].tolist() == [0.0, 0.0] and jp[2].tolist() == [0.0, 0.0]
    assert jp[1].tolist() == pytest.approx([0.5, 0.2]) and jp[3].tolist() == pytest.approx([0.5, 0.2])


@pytest.mark.parametrize("device", DEVICES)
def test_effort_target_drives_the_cart(device):
    """A constant 10 N on the 2 kg cart+pole (pole upright, damping 10) accelerates it along +y."""
    sim, scene = make_scene(CartpoleSceneCfg(num_envs=2, env_spacing=2.0), device, dt=0.002)
    robot = scene["cartpole"]
    effort = torch.tensor([[10.0, 0.0], [-10.0, 0.0]], device=sim.device)
    robot.set_joint_effort_target(effort)
    step(sim, scene, 9)
    vel = robot.data.joint_vel[:, 0].cpu().clone()  # the velocity the last step starts from
    step(sim, scene)
    assert vel[0] > 0.05 and vel[1] < -0.05
    # applied torque is what the last step applied: the effort minus damping 10 * v at its start
    torch.testing.assert_close(robot.data.applied_torque[:, 0].cpu(), effort[:, 0].cpu() - 10 * vel, atol=1e-4, rtol=0)
    # and the joint acceleration is that step's: its velocity change over dt
    acc = (robot.data.joint_vel[:, 0].cpu() - vel) / 0.002
    torch.testing.assert_close(robot.data.joint_acc[:, 0].cpu(), acc, atol=0.05, rtol=0.01)
    # the effort limit (400 N) clamps what MuJoCo applies
    robot.set_joint_effort_target(torch.full((2, 1), 1e4, device=sim.device), joint_ids=[0])
    step(sim, scene)
    assert robot.data.applied_torque[:, 0].max().item() <= 400.0 + 1e-3


def pd_robot_cfg(actuator_cfg) -> ArticulationCfg:
    return CARTPOLE_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot", actuators={"all": actuator_cfg})


@pytest.mark.parametrize(
    "actuator",
    [
        ImplicitActuatorCfg(joint_names_expr=[".*"], stiffness=400.0, damping=40.0, effort_limit_sim=1000.0),
        IdealPDActuatorCfg(joint_names_expr=[".*"], stiffness=400.0, damping=40.0, effort_limit=1000.0),
    ],
    ids=["implicit", "ideal_pd"],
)
def test_position_targets_are_reached(actuator):
    @configclass
    class SceneCfg(InteractiveSceneCfg):
        robot = pd_robot_cfg(actuator)

    sim, scene = make_scene(SceneCfg(num_envs=2, env_spacing=2.0), "cpu", dt=0.005)
    robot = scene["robot"]
    target = torch.tensor([[0.3, 0.0], [-0.3, 0.0]])
    robot.set_joint_position_target(target)
    step(sim, scene, 600)
    torch.testing.assert_close(robot.data.joint_pos, target, atol=0.02, rtol=0)
    # what the model asked for and what MuJoCo applied agree once the error is small
    torch.testing.assert_close(robot.data.computed_torque, robot.data.applied_torque, atol=2.0, rtol=0)


def test_dc_motor_torque_speed_curve():
    cfg = DCMotorCfg(
        joint_names_expr=["slider_to_cart"],
        stiffness=0.0,
        damping=0.0,
        saturation_effort=100.0,
        effort_limit=80.0,
        velocity_limit=2.0,
    )

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        robot = CARTPOLE_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot", actuators={"cart": cfg})

    sim, scene = make_scene(SceneCfg(num_envs=3, env_spacing=2.0), "cpu")
    robot = scene["robot"]
    robot.write_joint_state_to_sim(torch.zeros(3, 2), torch.tensor([[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]]))
    robot.set_joint_effort_target(torch.full((3, 1), 500.0), joint_ids=[0])
    robot.write_data_to_sim()
    # at 0 m/s: min(100, 80) = 80; at 1 m/s: 100 * (1 - 1/2) = 50; at 3 m/s, past the no-load
    # speed, the motor can only brake: 100 * (1 - 3/2) = -50
    motor = robot.actuators["cart"]
    assert motor.applied_effort[:, 0].tolist() == pytest.approx([80.0, 50.0, -50.0])
    assert motor.computed_effort[:, 0].tolist() == [500.0] * 3  # before the curve: what the PD law asked for
    assert robot.data.computed_torque[:, 0].tolist() == [500.0] * 3
    assert sim.physics.data("ctrl")[:, 0].tolist() == pytest.approx([80.0, 50.0, -50.0])


@pytest.mark.parametrize("device", DEVICES)
def test_rigid_object_free_fall_and_velocity_frames(device):
    sim, scene = make_scene(CubeSceneCfg(num_envs=2, env_spacing=2.0), device, dt=0.002)
    cube = scene["cube"]
    assert not cube.is_fixed_base
    torch.testing.assert_close(
        cube.data.root_pos_w, scene.env_origins + torch.tensor([0.0, 0.0, 1.0], device=sim.device)
    )
    step(sim, scene, 100)  # 0.2 s of free fall: v = -g t
    assert cube.data.root_lin_vel_w[:, 2].cpu().tolist() == pytest.approx([-9.81 * 0.2] * 2, rel=1e-3)

    # Angular velocity is written and read in the world frame, whatever the orientation.
    quat = math_utils.quat_from_euler_xyz(torch.tensor([0.3]), torch.tensor([-0.4]), torch.tensor([1.0])).to(sim.device)
    pose = torch.cat([scene.env_origins + torch.tensor([0.0, 0.0, 1.0], device=sim.device), quat.repeat(2, 1)], dim=-1)
    cube.write_root_pose_to_sim(pose)
    vel = torch.tensor([[0.0, 0.0, 0.0, 1.0, 2.0, 3.0]] * 2, device=sim.device)
    cube.write_root_velocity_to_sim(vel)
    sim.forward()
    torch.testing.assert_close(cube.data.root_ang_vel_w, vel[:, 3:], atol=1e-5, rtol=0)
    torch.testing.assert_close(cube.data.body_ang_vel_w[:, 0], vel[:, 3:], atol=1e-5, rtol=0)
    expected_b = math_utils.quat_apply_inverse(quat.repeat(2, 1), vel[:, 3:])
    torch.testing.assert_close(cube.data.root_ang_vel_b, expected_b, atol=1e-5, rtol=0)


@pytest.mark.parametrize("device", DEVICES)
def test_external_force_accelerates_body(device):
    sim, scene = make_scene(CubeSceneCfg(num_envs=2, env_spacing=2.0), device, dt=0.002, gravity=(0.0, 0.0, 0.0))
    cube = scene["cube"]
    forces = torch.tensor([[[4.0, 0.0, 0.0]], [[0.0, -2.0, 0.0]]], device=sim.device)
    cube.set_external_force_and_torque(forces, torch.zeros_like(forces), is_global=True)
    step(sim, scene, 50)  # 0.1 s at a = F / 2 kg
    torch.testing.assert_close(
        cube.data.root_lin_vel_w[:, :2].cpu(), torch.tensor([[0.2, 0.0], [0.0, -0.1]]), atol=1e-4, rtol=0
    )


@pytest.mark.parametrize("device", DEVICES)
def test_per_world_gravity(device):
    sim, scene = make_scene(CubeSceneCfg(num_envs=2, env_spacing=2.0), device, dt=0.002)
    gravity = sim.physics.model_field("opt.gravity")
    gravity[1] = torch.tensor([0.0, 0.0, -1.0], device=sim.device)
    step(sim, scene, 100)
    vz = scene["cube"].data.root_lin_vel_w[:, 2].cpu()
    assert vz.tolist() == pytest.approx([-9.81 * 0.2, -1.0 * 0.2], rel=1e-3)


def test_unknown_actuator_joint_is_named():
    @configclass
    class SceneCfg(InteractiveSceneCfg):
        robot = CARTPOLE_CFG.replace(
            prim_path="{ENV_REGEX_NS}/Robot",
            actuators={"x": ImplicitActuatorCfg(joint_names_expr=["elbow"], stiffness=0.0, damping=0.0)},
        )

    sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    with pytest.raises(ValueError, match="(?s)elbow.*slider_to_cart"):
        InteractiveScene(SceneCfg(num_envs=1, env_spacing=1.0))


def test_missing_scene_fields_are_reported():
    sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    with pytest.raises(ValueError, match="env_spacing"):
        InteractiveScene(InteractiveSceneCfg(num_envs=2))


def test_initial_joint_positions_from_config():
    @configclass
    class SceneCfg(InteractiveSceneCfg):
        robot = CARTPOLE_CFG.replace(
            prim_path="{ENV_REGEX_NS}/Robot",
            init_state=ArticulationCfg.InitialStateCfg(pos=(0.0, 0.0, 2.0), joint_pos={"cart_to_pole": math.pi / 8}),
        )

    sim, scene = make_scene(SceneCfg(num_envs=2, env_spacing=1.0), "cpu")
    robot = scene["robot"]
    assert robot.data.default_joint_pos[0].tolist() == pytest.approx([0.0, math.pi / 8])
    assert robot.data.joint_pos[1].tolist() == pytest.approx([0.0, math.pi / 8])


URDF = """<?xml version="1.0"?>
<robot name="arm">
  <link name="base">
    <inertial><mass value="2.0"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision>
  </link>
  <link name="upper">
    <inertial>
      <origin xyz="0 0 0.25"/><mass value="1.0"/>
      <inertia ixx="0.02" iyy="0.02" izz="0.001" ixy="0" ixz="0" iyz="0"/>
    </inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>
    <limit lower="-1.5" upper="1.5" effort="50" velocity="5"/>
  </joint>
</robot>
"""


@pytest.mark.parametrize("fix_base", [True, False])
def test_urdf_robot(tmp_path, fix_base):
    path = tmp_path / "arm.urdf"
    path.write_text(URDF)

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
        arm = ArticulationCfg(
            prim_path="{ENV_REGEX_NS}/Arm",
            spawn=sim_utils.UrdfFileCfg(asset_path=str(path), fix_base=fix_base),
            init_state=ArticulationCfg.InitialStateCfg(pos=(0.0, 0.0, 0.5), joint_pos={"shoulder": 0.3}),
            actuators={"arm": ImplicitActuatorCfg(joint_names_expr=["shoulder"], stiffness=100.0, damping=10.0)},
        )

    sim, scene = make_scene(SceneCfg(num_envs=2, env_spacing=2.0), "cpu", dt=0.005)
    arm = scene["arm"]
    assert arm.joint_names == ["shoulder"] and arm.body_names == ["base", "upper"]
    assert arm.is_fixed_base == fix_base
    assert arm.data.joint_pos_limits[0, 0].tolist() == pytest.approx([-1.5, 1.5])
    assert arm.data.default_mass[0].tolist() == pytest.approx([2.0, 1.0])
    assert arm.data.joint_pos[:, 0].tolist() == pytest.approx([0.3, 0.3])
    arm.set_joint_position_target(torch.full((2, 1), -0.5))
    step(sim, scene, 400)
    z = arm.data.root_pos_w[:, 2]
    if fix_base:
        assert torch.allclose(z, torch.tensor([0.5, 0.5]))
        assert arm.data.joint_pos[:, 0].tolist() == pytest.approx([-0.5, -0.5], abs=0.05)
    else:
        assert (z < 0.2).all(), "a floating base falls onto the ground"
