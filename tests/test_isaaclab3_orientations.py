"""Orientations Isaac Lab 3.0 code gives outside ``init_state`` and sensor offsets (issue 42.1): spawners'
``orientation=`` and ``create_prim`` (simlab.v3.sim), action terms' ``body_offset``, the pose command and
the quaternion observations (simlab.v3.envs.mdp). The same rotation written for 3.0 in (x, y, z, w) and for
2.x in (w, x, y, z) lands the same; a 3.0 value that would reach a 2.x reader is refused."""

from __future__ import annotations

import dataclasses
import math

import mujoco
import pytest
import torch

import simlab.sim as sim2
import simlab.utils.math as math2
import simlab.v3.envs.mdp as mdp3
import simlab.v3.sim as sim3
import simlab.v3.utils.math as math3
from simlab import assets as assets2
from simlab import scene as scene2
from simlab.envs import ManagerBasedRLEnv
from simlab.utils import configclass
from simlab.utils.errors import ConfigError
from simlab.v3 import assets as assets3
from simlab.v3 import envs as envs3
from simlab.v3 import scene as scene3

C, S = math.cos(math.pi / 4), math.sin(math.pi / 4)
Q_WXYZ = math2.quat_mul(
    torch.tensor([C, 0.0, 0.0, S]), torch.tensor([math.cos(math.pi / 12), math.sin(math.pi / 12), 0, 0])
)
Q_XYZW = math3.xyzw_from_wxyz(Q_WXYZ)


def _cuboid(module):
    return module.CuboidCfg(size=(0.4, 0.2, 0.1))


def test_a_spawners_orientation_in_3_0_order_lands_as_2_x_s():
    sim = sim2.SimulationContext(sim2.SimulationCfg(device="cpu"))
    cfg2, cfg3 = _cuboid(sim2), _cuboid(sim3)
    body2 = cfg2.func("/World/Box2", cfg2, translation=(0.0, 1.0, 1.0), orientation=tuple(Q_WXYZ.tolist()))
    body3 = cfg3.func("/World/Box3", cfg3, translation=(0.0, 2.0, 1.0), orientation=tuple(Q_XYZW.tolist()))
    assert type(cfg3).quat_order == "xyzw" and isinstance(cfg3, sim2.CuboidCfg)
    assert torch.allclose(torch.tensor(body3.quat), torch.tensor(body2.quat), atol=1e-6)
    assert torch.allclose(torch.tensor(body2.quat, dtype=torch.float32), Q_WXYZ, atol=1e-6)
    spawn3 = sim3.spawn_shape("/World/Box4", cfg3, translation=(0.0, 3.0, 1.0), orientation=tuple(Q_XYZW.tolist()))
    assert torch.allclose(torch.tensor(spawn3.quat), torch.tensor(body2.quat), atol=1e-6)
    sim.reset()
    model = sim.model
    quat = {n: model.body_quat[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, b.name)] for n, b in
            (("2", body2), ("3", body3))}  # fmt: skip
    assert torch.allclose(torch.tensor(quat["3"]), torch.tensor(quat["2"]), atol=1e-6)


def test_3_0_orientations_are_checked_and_2_x_s_identity_is_refused():
    sim2.SimulationContext(sim2.SimulationCfg(device="cpu"))
    cfg3 = _cuboid(sim3)
    with pytest.raises(ConfigError, match=r"rot=\(1, 0, 0, 0\) is Isaac Lab 2.x's identity .* takes \(x, y, z, w\)"):
        cfg3.func("/World/Box", cfg3, orientation=(1, 0, 0, 0))
    with pytest.raises(ConfigError, match="not a unit quaternion; Isaac Lab 3.0 configs take"):
        cfg3.func("/World/Box", cfg3, orientation=(0, 0, 0, 2))
    # 3.0's identity (0, 0, 0, 1) is an Xform's only orientation, as (1, 0, 0, 0) is 2.x's
    assert sim3.create_prim("/World/Origin1", "Xform", translation=(1.0, 0.0, 0.0), orientation=(0, 0, 0, 1))
    with pytest.raises(NotImplementedError, match="an Xform group in simlab carries a translation only"):
        sim2.create_prim("/World/Origin2", "Xform", orientation=(0, 0, 0, 1))  # 2.x reads a half turn about x


def test_a_3_0_spawner_config_in_a_scene_lands_as_2_x_s_and_a_2_x_scene_refuses_it():
    @configclass
    class SceneCfg(scene3.InteractiveSceneCfg):
        box2 = assets3.RigidObjectCfg(
            prim_path="{ENV_REGEX_NS}/Box2",
            spawn=sim2.CuboidCfg(size=(0.4, 0.2, 0.1), rigid_props=sim2.RigidBodyPropertiesCfg(disable_gravity=True)),
            init_state=assets3.RigidObjectCfg.InitialStateCfg(pos=(0.0, 1.0, 1.0), rot=tuple(Q_XYZW.tolist())),
        )
        box3 = assets3.RigidObjectCfg(
            prim_path="{ENV_REGEX_NS}/Box3",
            spawn=sim3.CuboidCfg(size=(0.4, 0.2, 0.1), rigid_props=sim3.RigidBodyPropertiesCfg(disable_gravity=True)),
            init_state=assets3.RigidObjectCfg.InitialStateCfg(pos=(0.0, 2.0, 1.0), rot=tuple(Q_XYZW.tolist())),
        )

    sim = sim2.SimulationContext(sim2.SimulationCfg(device="cpu"))
    scene = scene3.InteractiveScene(SceneCfg(num_envs=2, env_spacing=3.0))
    sim.reset()
    scene.update(sim.get_physics_dt())
    assert torch.allclose(scene["box3"].data.root_quat_w, scene["box2"].data.root_quat_w, atol=1e-5)
    assert torch.allclose(scene["box3"].data.root_quat_w, Q_WXYZ.expand(2, 4), atol=1e-5)
    sim2.SimulationContext.clear_instance()

    @configclass
    class Scene2Cfg(scene2.InteractiveSceneCfg):
        box = assets2.RigidObjectCfg(prim_path="{ENV_REGEX_NS}/Box", spawn=sim3.CuboidCfg(size=(0.1, 0.1, 0.1)))

    sim2.SimulationContext(sim2.SimulationCfg(device="cpu"))
    with pytest.raises(ConfigError, match="is Isaac Lab 3.0's.*simlab's 2.x"):
        scene2.InteractiveScene(Scene2Cfg(num_envs=1, env_spacing=1.0))


def _reach_cfg(offset):
    from simlab.tasks.manager_based.manipulation.reach.config.franka.ik_abs_env_cfg import FrankaReachEnvCfg

    cfg = FrankaReachEnvCfg()
    cfg.scene.num_envs, cfg.sim.device = 2, "cpu"
    cfg.actions.arm_action.body_offset = offset
    return cfg


def test_an_action_terms_body_offset_in_3_0_order_gives_the_same_end_effector_frame():
    offset2 = mdp3.DifferentialInverseKinematicsActionCfg.__mro__[1].OffsetCfg(
        pos=(0.0, 0.0, 0.107), rot=tuple(Q_WXYZ.tolist())
    )
    offset3 = mdp3.DifferentialInverseKinematicsActionCfg.OffsetCfg(pos=(0.0, 0.0, 0.107), rot=tuple(Q_XYZW.tolist()))
    assert type(offset3).quat_order == "xyzw"
    env2 = ManagerBasedRLEnv(_reach_cfg(offset2))
    pos2, quat2 = env2.action_manager.get_term("arm_action")._ee_pose_b()
    env2.close()
    cfg3 = _reach_cfg(offset3)
    old = cfg3.commands.ee_pose
    fields = {f.name: getattr(old, f.name) for f in dataclasses.fields(old) if f.name != "class_type"}
    cfg3.commands.ee_pose = mdp3.UniformPoseCommandCfg(**fields)  # 3.0's pose command
    env3 = envs3.ManagerBasedRLEnv(cfg3)
    try:
        pos3, quat3 = env3.action_manager.get_term("arm_action")._ee_pose_b()
        assert torch.allclose(pos3, pos2, atol=1e-5) and torch.allclose(quat3, quat2, atol=1e-5)
        # 3.0 code reads the pose command (x, y, z, qx, qy, qz, qw); simlab's term keeps its own order inside
        term = env3.command_manager.get_term("ee_pose")
        command = env3.command_manager.get_command("ee_pose")
        assert torch.equal(command[:, 3:], term.pose_command_b[:, [4, 5, 6, 3]])
        root = mdp3.root_quat_w(env3)
        assert torch.equal(root, env3.scene["robot"].data.root_quat_w.torch)
        assert torch.allclose(
            mdp3.body_pose_w(env3).view(2, -1, 7)[..., 3:], env3.scene["robot"].data.body_quat_w.torch
        )
    finally:
        env3.close()


def test_a_3_0_body_offset_in_a_2_x_env_is_refused():
    offset3 = mdp3.DifferentialInverseKinematicsActionCfg.OffsetCfg(pos=(0.0, 0.0, 0.1), rot=(0.0, 0.0, 0.0, 1.0))
    with pytest.raises(ConfigError, match=r"FrankaReachEnvCfg.actions.arm_action.body_offset is Isaac Lab 3.0's"):
        ManagerBasedRLEnv(_reach_cfg(offset3))
