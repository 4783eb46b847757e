"""Isaac Lab 3.0's asset API on simlab (simlab.v3, issue 42.1/42.3/42.4): data read through ``.torch`` in
(x, y, z, w), the ``_index`` / ``_mask`` writers, ``actuators.target_command``; Isaac Lab 3.0's own files
(tests/ported3, each with its import mapping and what else differs written at its top) step on it, and
2.x code reading the same assets keeps (w, x, y, z)."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest
import torch

import simlab.sim as sim_utils
import simlab.utils.math as math2
import simlab.v3.utils.math as math3
from simlab import assets as assets2
from simlab import scene as scene2
from simlab.robots import ANT_CFG, CARTPOLE_CFG
from simlab.sim import SimulationContext
from simlab.utils import configclass
from simlab.v3 import assets as assets3
from simlab.v3 import scene as scene3
from simlab.v3._proxy import ProxyTensor

ROOT = Path(__file__).resolve().parents[1]
PORTED3 = Path(__file__).parent / "ported3"

# one rotation: roll 0.4, pitch 0.2, yaw 1.1 (rad)
Q_WXYZ = math2.quat_from_euler_xyz(torch.tensor([0.4]), torch.tensor([0.2]), torch.tensor([1.1]))[0]
Q_XYZW = math3.xyzw_from_wxyz(Q_WXYZ)


@pytest.fixture
def ported3():
    sys.path.insert(0, str(PORTED3))
    yield
    sys.path.remove(str(PORTED3))
    for name in [m for m in sys.modules if m.split(".")[0].startswith("isaaclab3_")]:
        del sys.modules[name]


def _box(cfg_module, y: float, rot=(1.0, 0.0, 0.0, 0.0)):
    return cfg_module.RigidObjectCfg(
        prim_path=f"{{ENV_REGEX_NS}}/Box{int(y)}",
        spawn=sim_utils.CuboidCfg(
            size=(0.4, 0.2, 0.1),
            rigid_props=sim_utils.RigidBodyPropertiesCfg(disable_gravity=True),
            mass_props=sim_utils.MassPropertiesCfg(mass=1.0),
        ),
        init_state=cfg_module.RigidObjectCfg.InitialStateCfg(pos=(0.0, y, 1.0), rot=rot),
    )


@configclass
class _SceneCfg(scene3.InteractiveSceneCfg):
    robot = CARTPOLE_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")  # a 2.x robot config in a 3.0 scene
    box = _box(assets2, 1.0, tuple(Q_WXYZ.tolist()))  # 2.x config: (w, x, y, z)
    box3 = _box(assets3, 2.0, tuple(Q_XYZW.tolist()))  # 3.0 config: (x, y, z, w)


def _scene(cfg_class=_SceneCfg, num_envs: int = 2):
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    scene = scene3.InteractiveScene(cfg_class(num_envs=num_envs, env_spacing=3.0))
    sim.reset()
    scene.update(sim.get_physics_dt())
    return sim, scene


def test_3_0_code_reads_xyzw_and_2_x_code_reads_wxyz_from_the_same_assets():
    _, scene = _scene()
    for name in ("box", "box3"):
        data = scene[name].data
        assert isinstance(scene[name], assets3.RigidObject)
        # 2.x code: the tensor itself, (w, x, y, z); 3.0 code: .torch, (x, y, z, w)
        assert torch.allclose(data.root_quat_w, Q_WXYZ.expand(2, 4), atol=1e-5)
        assert torch.allclose(data.root_quat_w.torch, Q_XYZW.expand(2, 4), atol=1e-5)
        assert torch.allclose(data.root_state_w.torch[:, 3:7], Q_XYZW.expand(2, 4), atol=1e-5)
        assert torch.allclose(data.root_pose_w.torch[:, :3], data.root_pos_w, atol=1e-6)
        assert torch.allclose(data.body_quat_w.torch[:, 0], Q_XYZW.expand(2, 4), atol=1e-5)
        assert torch.allclose(data.default_root_pose.torch[:, 3:], Q_XYZW.expand(2, 4), atol=1e-5)
        assert torch.equal(data.default_root_vel.torch, data.default_root_state[:, 7:])
    quat = scene["box"].data.root_quat_w
    x_axis = torch.tensor([[1.0, 0.0, 0.0]]).expand(2, 3)
    # each math reads its own order; a proxy handed to 3.0's math without .torch is read as 3.0 reads it
    expected = math2.quat_apply(quat, x_axis)
    assert torch.allclose(math3.quat_apply(quat.torch, x_axis), expected, atol=1e-6)
    assert torch.allclose(math3.quat_apply(quat, x_axis), expected, atol=1e-6)
    # what 2.x code computes from a proxy is a plain tensor: the proxy does not spread
    assert type(quat[:, 0]) is torch.Tensor and type(quat * 2) is torch.Tensor
    assert isinstance(scene["robot"].data.joint_pos, ProxyTensor)
    assert scene["robot"].data.joint_pos.torch.data_ptr() == scene["robot"].data.joint_pos.data_ptr()  # no copy
    assert scene["robot"].data.joint_pos.warp.shape == (2, 2)


def test_a_2_x_scene_keeps_2_x_assets():
    """3.0's names exist only on the assets of 3.0 scenes, envs and classes: 2.x code is unchanged and
    3.0 code given a 2.x asset stops at the first 3.0 name."""

    @configclass
    class SceneCfg(scene2.InteractiveSceneCfg):
        robot = CARTPOLE_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    scene = scene2.InteractiveScene(SceneCfg(num_envs=1, env_spacing=2.0))
    sim.reset()
    robot = scene["robot"]
    assert type(robot) is assets2.Articulation and type(robot.data.joint_pos) is torch.Tensor
    with pytest.raises(AttributeError, match="torch"):
        robot.data.joint_pos.torch  # noqa: B018
    with pytest.raises(AttributeError, match="write_root_pose_to_sim_index"):
        robot.write_root_pose_to_sim_index(root_pose=robot.data.root_pose_w)


def test_index_and_mask_writers_take_3_0_values_and_write_simlabs():
    sim, scene = _scene()
    box, robot = scene["box"], scene["robot"]
    # a pose (x, y, z, w) for env 1 only
    pose = torch.cat([scene.env_origins[1] + torch.tensor([0.5, 0.0, 2.0]), Q_XYZW]).unsqueeze(0)
    before = box.data.root_quat_w.clone()
    box.write_root_pose_to_sim_index(root_pose=pose, env_ids=[1])
    assert torch.allclose(box.data.root_quat_w[1], Q_WXYZ, atol=1e-5)  # 2.x code reads it (w, x, y, z)
    assert torch.allclose(box.data.root_pos_w[1], pose[0, :3], atol=1e-5)
    assert torch.equal(box.data.root_quat_w[0], before[0])
    # the mask writer: full data, a row per env, written where the mask is set
    identity = torch.tensor([0.0, 0.0, 0.0, 1.0])
    full = torch.cat([box.data.root_pos_w, identity.expand(2, 4)], dim=-1)
    box.write_root_pose_to_sim_mask(root_pose=full, env_mask=torch.tensor([True, False]))
    assert torch.allclose(box.data.root_quat_w[0], torch.tensor([1.0, 0.0, 0.0, 0.0]))
    assert torch.allclose(box.data.root_quat_w[1], Q_WXYZ, atol=1e-5)
    # a proxy handed back without .torch (3.0's bridge) is read as 3.0 reads it: writing it changes nothing
    state = box.data.root_quat_w.clone()
    box.write_root_pose_to_sim_mask(root_pose=box.data.root_pose_w)
    assert torch.allclose(box.data.root_quat_w, state, atol=1e-6)
    box.write_root_velocity_to_sim_index(root_velocity=torch.tensor([[0.0, 0.0, 0.0, 0.0, 0.0, 2.0]]), env_ids=[0])
    assert torch.allclose(box.data.root_ang_vel_w[0], torch.tensor([0.0, 0.0, 2.0]), atol=1e-5)

    # joints: ids select partial data, masks select from full data
    robot.write_joint_position_to_sim_index(position=torch.tensor([[0.3]]), joint_ids=[1], env_ids=[0])
    robot.write_joint_velocity_to_sim_mask(
        velocity=torch.full((2, 2), 0.7), joint_mask=torch.tensor([True, False]), env_mask=torch.tensor([False, True])
    )
    assert torch.allclose(robot.data.joint_pos.torch[:, 1], torch.tensor([0.3, 0.0]))
    assert torch.allclose(robot.data.joint_vel.torch, torch.tensor([[0.0, 0.0], [0.7, 0.0]]))
    robot.write_joint_damping_to_sim_index(damping=3.0, joint_ids=[1])
    assert torch.equal(robot.data.joint_damping[:, 1], torch.tensor([3.0, 3.0]))
    robot.set_joint_effort_target_index(target=torch.ones(2, 1), joint_ids=[0])
    robot.actuators.target_command.set_effort_index(value=torch.full((1, 1), 2.0), joint_ids=[0], env_ids=[1])
    assert torch.equal(robot.actuators.target_command.effort.torch[:, 0], torch.tensor([1.0, 2.0]))
    assert torch.equal(robot.data.joint_effort_target[:, 0], torch.tensor([1.0, 2.0]))  # the same buffer, 2.x's name
    robot.write_data_to_sim()
    sim.step()
    scene.update(sim.get_physics_dt())
    applied = robot.actuators.applied_effort.torch
    assert torch.equal(applied, robot.data.applied_torque) and applied[0, 0] == 1.0  # env 0: at rest, no damping
    assert torch.equal(robot.actuators.computed_effort.torch, robot.data.computed_torque)
    assert set(robot.actuators) == {"cart_actuator", "pole_actuator"}  # the groups, as 2.x's dict

    # 3.0's writers are keyword-only and say what they take
    with pytest.raises(TypeError, match=r"write_root_pose_to_sim_index\(\): missing \['root_pose'\]; .* root_pose="):
        box.write_root_pose_to_sim_index(pose=pose)
    with pytest.raises(TypeError, match=r"unexpected \['env_mask'\]"):
        robot.write_joint_position_to_sim_index(position=torch.zeros(2, 2), env_mask=torch.ones(2, dtype=torch.bool))
    with pytest.raises(ValueError, match=r"env_mask must be a bool mask of shape \(2,\)"):
        box.write_root_velocity_to_sim_mask(root_velocity=torch.zeros(2, 6), env_mask=torch.tensor([0, 1]))


def test_a_rigid_object_collection_takes_3_0_body_writers():
    @configclass
    class SceneCfg(scene3.InteractiveSceneCfg):
        objects = assets3.RigidObjectCollectionCfg(
            rigid_objects={"a": _box(assets3, 1.0, tuple(Q_XYZW.tolist())), "b": _box(assets2, 2.0)}
        )

    _, scene = _scene(SceneCfg)
    objects = scene["objects"]
    assert isinstance(objects, assets3.RigidObjectCollection)
    data = objects.data
    assert torch.allclose(data.body_quat_w.torch[:, 0], Q_XYZW.expand(2, 4), atol=1e-5)  # 3.0 config, 3.0 read
    assert torch.allclose(data.object_quat_w[:, 0], Q_WXYZ.expand(2, 4), atol=1e-5)  # 2.x read
    assert torch.allclose(data.default_body_pose.torch[:, 0, 3:], Q_XYZW.expand(2, 4), atol=1e-5)
    # body "b" of env 1 turned by Q, given (x, y, z, w); nothing else moves
    before = data.object_quat_w.clone()
    pose = torch.cat([data.body_pos_w[1:, 1], Q_XYZW.unsqueeze(0)], dim=-1).unsqueeze(1)  # (1 env, 1 body, 7)
    objects.write_body_pose_to_sim_index(body_poses=pose, env_ids=[1], body_ids=[1])
    assert torch.allclose(data.object_quat_w[1, 1], Q_WXYZ, atol=1e-5)
    assert torch.equal(data.object_quat_w[0], before[0]) and torch.equal(data.object_quat_w[1, 0], before[1, 0])
    velocities = torch.zeros(2, 2, 6)
    velocities[..., 2] = 1.5
    objects.write_body_com_velocity_to_sim_mask(
        body_velocities=velocities, env_mask=torch.tensor([True, False]), body_mask=torch.tensor([False, True])
    )
    assert torch.allclose(data.object_lin_vel_w[:, :, 2], torch.tensor([[0.0, 1.5], [0.0, 0.0]]))


def test_3_0_robot_configs_are_simlabs_in_3_0_order():
    """``isaaclab_assets`` -> ``simlab.v3.robots``: a robot's ``rot`` read by 3.0 code is (x, y, z, w), it
    builds with 3.0's API, and it gives the pose of simlab's 2.x config, which stays as it was."""
    import simlab.robots as robots2
    import simlab.v3.robots as robots3

    hand3 = robots3.ALLEGRO_HAND_CFG
    w, x, y, z = robots2.ALLEGRO_HAND_CFG.init_state.rot  # a turned hand: (w, x, y, z) in 2.x
    assert hand3.init_state.rot == (x, y, z, w) and robots2.ALLEGRO_HAND_CFG.init_state.rot == (w, x, y, z)
    assert hand3.class_type is assets3.Articulation and isinstance(hand3, assets3.ArticulationCfg)
    assert robots3.CARTPOLE_CFG.init_state.rot == (0.0, 0.0, 0.0, 1.0)
    hand3.spawn.func = None  # a 3.0 config shares nothing with simlab's
    assert robots2.ALLEGRO_HAND_CFG.spawn.func is not None
    assert robots3.CART_DOUBLE_PENDULUM_CFG.actuators.keys() == robots2.CART_DOUBLE_PENDULUM_CFG.actuators.keys()

    @configclass
    class SceneCfg(scene3.InteractiveSceneCfg):
        hand2 = robots2.ALLEGRO_HAND_CFG.replace(prim_path="{ENV_REGEX_NS}/Hand2")
        hand3 = robots3.ALLEGRO_HAND_CFG.replace(prim_path="{ENV_REGEX_NS}/Hand3")

    _, scene = _scene(SceneCfg, num_envs=1)
    quat2, quat3 = scene["hand2"].data.root_quat_w, scene["hand3"].data.root_quat_w
    assert torch.allclose(quat3, quat2, atol=1e-5) and torch.allclose(quat2[0], torch.tensor([w, x, y, z]), atol=1e-5)
    assert torch.allclose(quat3.torch[0], torch.tensor(hand3.init_state.rot), atol=1e-5)


def test_the_3_0_articulation_tutorial_runs():
    """Isaac Lab 3.0's run_articulation.py (tests/ported3): resets through default_root_pose and the
    _index writers, drives through actuators.target_command."""
    result = subprocess.run(
        [sys.executable, str(PORTED3 / "run_articulation.py"), "--headless", "--device", "cpu"]
        + ["--max_app_steps", "501"],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=ROOT,
    )
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    assert "Setup complete" in result.stdout and result.stdout.count("Resetting robot state") == 2  # steps 0, 500


def test_the_3_0_manager_based_cartpole_steps(ported3):
    from isaaclab3_cartpole.cartpole_manager_env_cfg import CartpoleEnvCfg
    from isaaclab3_cartpole.mdp import joint_pos_target_l2

    import simlab.v3.envs
    from simlab.managers import SceneEntityCfg
    from simlab.tasks.manager_based.classic.cartpole import mdp as mdp2

    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs, cfg.sim.device = 4, "cpu"
    env = simlab.v3.envs.ManagerBasedRLEnv(cfg)
    env.reset(seed=0)
    pole = SceneEntityCfg("robot", joint_names=["cart_to_pole"])
    pole.resolve(env.scene)
    episode_rewards = []
    for _ in range(320):  # past the 5 s time out (300 env steps)
        _, reward, _, _, extras = env.step(torch.zeros(4, 1))
        assert torch.isfinite(reward).all()
        # the 3.0 reward (.torch) and simlab's 2.x reward read the same joint
        assert torch.allclose(joint_pos_target_l2(env, 0.0, pole), mdp2.joint_pos_target_l2(env, 0.0, pole))
        if "Episode_Reward/pole_pos" in extras["log"]:
            episode_rewards.append(extras["log"]["Episode_Reward/pole_pos"])
    light_rot = env.cfg.scene.distant_light.init_state.rot
    env.close()
    assert any(float(r) < 0.0 for r in episode_rewards)  # the 3.0 term, summed over the episodes that ended
    # the light's (x, y, z, w) from 3.0's constants, converted once for simlab's (w, x, y, z)
    angle = torch.tensor([-math.pi / 4])
    expected = math2.quat_from_euler_xyz(torch.zeros(1), angle, angle)
    assert torch.allclose(torch.tensor(light_rot), expected[0], atol=1e-6)


def test_the_3_0_direct_cartpole_steps(ported3):
    from isaaclab3_cartpole.cartpole_direct_env import CartpoleEnv
    from isaaclab3_cartpole.cartpole_direct_env_cfg import CartpoleEnvCfg

    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs, cfg.sim.device = 4, "cpu"
    env = CartpoleEnv(cfg)
    obs, _ = env.reset(seed=0)
    robot = env.cartpole
    assert isinstance(robot, assets3.Articulation)
    # after the reset through default_root_pose and write_root_pose_to_sim_index: at each env origin, upright
    assert torch.allclose(robot.data.root_pos_w, env.scene.env_origins + torch.tensor([0.0, 0.0, 2.0]), atol=1e-5)
    assert torch.allclose(robot.data.root_quat_w.torch, torch.tensor([0.0, 0.0, 0.0, 1.0]).expand(4, 4))
    pole = obs["policy"][:, 1]
    assert (pole.abs() <= math.pi / 4 + 1e-6).all() and pole.abs().max() > 0.0  # sampled in 3.0's range
    resets = 0
    for _ in range(200):
        obs, reward, terminated, truncated, extras = env.step(torch.ones(4, 1))  # full push: the cart leaves
        resets += int((terminated | truncated).sum())
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
    env.close()
    assert resets > 0 and "Metrics/success_rate" in extras["log"]


def _tilt(robot, env_origins: torch.Tensor) -> None:
    """Each env's robot turned a different way, written by 2.x code in (w, x, y, z)."""
    n = env_origins.shape[0]
    roll, pitch, yaw = torch.linspace(-0.5, 0.6, n), torch.linspace(0.3, -0.2, n), torch.linspace(-2.5, 2.9, n)
    pose = torch.cat([env_origins + torch.tensor([0.3, -0.2, 1.0]), math2.quat_from_euler_xyz(roll, pitch, yaw)], -1)
    robot.write_root_pose_to_sim(pose)


def test_3_0_locomotion_terms_agree_with_simlabs_2_x_terms(ported3):
    """Isaac Lab 3.0's ant/humanoid observations and rewards (tests/ported3/isaaclab3_locomotion), in
    simlab's 2.x ant task built as a 3.0 env: the 3.0 terms read (x, y, z, w) through .torch, simlab's
    2.x terms read (w, x, y, z), from the same robot, step after step."""
    from isaaclab3_locomotion import mdp as mdp3

    import simlab.v3.envs
    from simlab.tasks.manager_based.classic.ant.ant_env_cfg import AntEnvCfg
    from simlab.tasks.manager_based.classic.humanoid import mdp as mdp2

    cfg = AntEnvCfg()
    cfg.scene.num_envs, cfg.sim.device = 3, "cpu"
    env = simlab.v3.envs.ManagerBasedRLEnv(cfg)
    env.reset(seed=0)
    robot = env.scene["robot"]
    _tilt(robot, env.scene.env_origins)
    env.sim.forward()
    target = (10.0, 5.0, 0.0)
    for step in range(4):
        if step:
            env.step(torch.rand(3, env.action_manager.total_action_dim) * 2 - 1)
        yaw_roll = mdp3.base_yaw_roll(env)
        assert torch.allclose(yaw_roll, mdp2.base_yaw_roll(env), atol=1e-5)
        assert torch.allclose(mdp3.base_up_proj(env), mdp2.base_up_proj(env), atol=1e-6)
        # 3.0's target is relative to each env's origin, simlab's 2.x term takes a world point
        for i in range(3):
            world = tuple((env.scene.env_origins[i] + torch.tensor(target)).tolist())
            assert torch.allclose(
                mdp3.base_heading_proj(env, target)[i], mdp2.base_heading_proj(env, world)[i], atol=1e-5
            )
            assert torch.allclose(
                mdp3.base_angle_to_target(env, target)[i], mdp2.base_angle_to_target(env, world)[i], atol=1e-5
            )
        assert torch.equal(mdp3.upright_posture_bonus(env, 0.93), (mdp2.base_up_proj(env)[:, 0] > 0.93).float())
    # the turns were read, not ignored: the envs' yaws differ as written
    assert yaw_roll[:, 0].max() - yaw_roll[:, 0].min() > 2.0
    env.close()


def test_3_0_lift_observation_reads_the_object_in_the_robot_frame(ported3):
    """Isaac Lab 3.0's lift ``object_position_in_robot_root_frame`` against simlab's 2.x term, with the
    robot's root turned (a floating ant as the robot, a box as the object)."""
    from isaaclab3_lift.mdp import object_position_in_robot_root_frame as obs3

    from simlab.tasks.manager_based.manipulation.lift.mdp import object_position_in_robot_root_frame as obs2

    @configclass
    class SceneCfg(scene3.InteractiveSceneCfg):
        robot = ANT_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        object = _box(assets3, 1.0, tuple(Q_XYZW.tolist()))

    sim, scene = _scene(SceneCfg, num_envs=3)
    _tilt(scene["robot"], scene.env_origins)
    env = SimpleNamespace(scene=scene, num_envs=3, device="cpu")
    for _ in range(3):
        sim.forward()
        expected = obs2(env)
        assert torch.allclose(obs3(env), expected, atol=1e-5)
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())
    # by hand: the box, seen from the turned root, is not where it is in the world frame
    rel_w = scene["object"].data.root_pos_w - scene["robot"].data.root_pos_w
    assert (expected - rel_w).norm(dim=-1).min() > 0.1
    SimulationContext.clear_instance()


def test_3_0_velocity_rewards_step_in_a_velocity_task_as_simlabs_2_x_terms(ported3):
    """Isaac Lab 3.0's velocity rewards (tests/ported3/isaaclab3_velocity: the contact sensor read through
    ``.torch`` and ``compute_first_contact(dt).torch``, the root through ``root_quat_w.torch``) run as the
    reward terms of simlab's Go1 flat task built as a 3.0 env, and give simlab's 2.x terms' values on
    robots turned a different way in each env, step after step."""
    from isaaclab3_velocity import mdp as mdp3

    import simlab.v3.envs
    from simlab.envs import mdp as mdp2
    from simlab.managers import SceneEntityCfg
    from simlab.tasks.manager_based.locomotion.velocity.config.go1.flat_env_cfg import UnitreeGo1FlatEnvCfg
    from simlab.v3 import sensors as sensors3

    cfg = UnitreeGo1FlatEnvCfg()
    cfg.scene.num_envs, cfg.sim.device = 3, "cpu"
    for name in ("feet_air_time", "track_lin_vel_xy_exp", "track_ang_vel_z_exp"):
        term = getattr(cfg.rewards, name)
        term.func = {
            "feet_air_time": mdp3.feet_air_time,
            "track_lin_vel_xy_exp": mdp3.track_lin_vel_xy_yaw_frame_exp,
            "track_ang_vel_z_exp": mdp3.track_ang_vel_z_world_exp,
        }[name]
    env = simlab.v3.envs.ManagerBasedRLEnv(cfg)
    env.reset(seed=0)
    sensor = env.scene.sensors["contact_forces"]
    assert isinstance(sensor, sensors3.ContactSensor)
    _tilt_yaw_only(env.scene["robot"], env.scene.env_origins)
    feet = SceneEntityCfg("contact_forces", body_names=".*foot")
    feet_bodies = SceneEntityCfg("robot", body_names=".*foot")
    feet.resolve(env.scene)
    feet_bodies.resolve(env.scene)
    contacts_seen = 0
    for _ in range(30):
        _, reward, *_ = env.step(torch.rand(3, env.action_manager.total_action_dim) * 2 - 1)
        assert torch.isfinite(reward).all()
        args = {"command_name": "base_velocity"}
        assert torch.allclose(
            mdp3.track_lin_vel_xy_yaw_frame_exp(env, std=0.5, **args),
            mdp2.track_lin_vel_xy_yaw_frame_exp(env, std=0.5, **args),
            atol=1e-6,
        )
        assert torch.allclose(
            mdp3.track_ang_vel_z_world_exp(env, std=0.5, **args),
            mdp2.track_ang_vel_z_world_exp(env, std=0.5, **args),
            atol=1e-6,
        )
        assert torch.equal(
            mdp3.feet_air_time(env, sensor_cfg=feet, threshold=0.1, **args),
            mdp2.feet_air_time(env, sensor_cfg=feet, threshold=0.1, **args),
        )
        assert torch.equal(
            mdp3.feet_air_time_positive_biped(env, threshold=0.4, sensor_cfg=feet, **args),
            mdp2.feet_air_time_positive_biped(env, threshold=0.4, sensor_cfg=feet, **args),
        )
        assert torch.allclose(
            mdp3.feet_slide(env, sensor_cfg=feet, asset_cfg=feet_bodies),
            mdp2.feet_slide(env, sensor_cfg=feet, asset_cfg=feet_bodies),
        )
        # 3.0's contact force names are simlab's tensors
        assert torch.equal(sensor.data.net_normal_forces_w.torch, sensor.data.net_forces_w)
        with pytest.raises(AttributeError, match="does not split friction"):  # no friction_forces_w in simlab
            sensor.data.friction_force_matrix_w  # noqa: B018
        contacts_seen += int((sensor.data.net_forces_w[:, feet.body_ids].norm(dim=-1) > 1.0).sum())
    env.close()
    assert contacts_seen > 0  # the feet touched: the contact terms were not all zeros


def _tilt_yaw_only(robot, env_origins: torch.Tensor) -> None:
    """Each env's robot standing turned to a different heading (2.x writer, (w, x, y, z))."""
    n = env_origins.shape[0]
    yaw = torch.linspace(-2.5, 2.9, n)
    quat = math2.quat_from_euler_xyz(torch.zeros(n), torch.zeros(n), yaw)
    pose = torch.cat([robot.data.root_pos_w[:, :3], quat], dim=-1)
    robot.write_root_pose_to_sim(pose)
