"""Derived quantities are computed when read (PhysicsBackend.ensure_forward): no forward is wasted,
none is missed, and trajectories are the same as with a forward after every step."""

from __future__ import annotations

import pytest
import torch
from conftest import DEVICES
from test_scene_articulation import CubeSceneCfg, make_scene

from simlab.sim import SimulationContext
from simlab.tasks.direct.cartpole.cartpole_env import CartpoleEnv, CartpoleEnvCfg
from simlab.tasks.direct.humanoid.humanoid_env import HumanoidEnv, HumanoidEnvCfg
from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleEnvCfg as CartpoleManagerEnvCfg


def count_forwards(physics) -> dict[str, int]:
    counter = {"forwards": 0}
    original = physics._forward

    def counted(env_ids):
        counter["forwards"] += 1
        original(env_ids)

    physics._forward = counted
    return counter


@pytest.mark.parametrize("workflow", ["direct", "manager"])
def test_a_step_reading_only_joint_states_runs_no_forward(workflow):
    from simlab.envs import ManagerBasedRLEnv

    if workflow == "direct":
        cfg = CartpoleEnvCfg(seed=0)
        cfg.scene.num_envs = 8
        env = CartpoleEnv(cfg)
    else:
        cfg = CartpoleManagerEnvCfg(seed=0)
        cfg.scene.num_envs = 8
        env = ManagerBasedRLEnv(cfg)
    env.reset()
    counter = count_forwards(env.sim.physics)
    for _ in range(60):  # long enough for episodes to end and reset
        env.step(torch.ones(8, 1))
    assert counter["forwards"] == 0
    # Reading a body pose forwards once, then again only after the state changes.
    robot = env.scene["cartpole" if workflow == "direct" else "robot"]
    pole_pos = robot.data.body_pos_w
    torch.testing.assert_close(robot.data.body_pos_w, pole_pos)  # nothing changed: no second forward
    assert counter["forwards"] == 1
    assert torch.isfinite(pole_pos).all()
    env.close()


@pytest.mark.parametrize("device", DEVICES)
def test_body_poses_follow_steps_and_writes(device):
    sim, scene = make_scene(CubeSceneCfg(num_envs=4, env_spacing=2.0), device)
    cube = scene["cube"]
    for _ in range(5):
        sim.physics.step(1, forward=False)  # as env loops step
    assert sim.physics.is_stale
    # The cube's body frame is its root: a current body pose equals the root pose in qpos.
    torch.testing.assert_close(cube.data.body_pos_w[:, 0], cube.data.root_pos_w)
    assert not sim.physics.kinematics_stale  # (the GPU backend's kinematics pass leaves the rest stale)

    pose = cube.data.root_pose_w.clone()
    pose[1:3, 2] += 0.5
    ids = torch.tensor([1, 2], device=sim.device)
    cube.write_root_pose_to_sim(pose[ids], env_ids=ids)
    assert sim.physics.is_stale
    torch.testing.assert_close(cube.data.body_pos_w[:, 0], pose[:, :3])


def run_humanoid(eager_forward: bool, steps: int = 40) -> list[torch.Tensor]:
    cfg = HumanoidEnvCfg(seed=3)
    cfg.scene.num_envs = 4
    env = HumanoidEnv(cfg)
    physics = env.sim.physics
    if eager_forward:  # the behaviour before lazy forwards: one after every step and every write
        step = physics.step
        physics.step = lambda nstep=1, forward=True: step(nstep, forward=True)
        physics.mark_stale = lambda env_ids=None: physics.forward(env_ids)
    obs, _ = env.reset()
    generator = torch.Generator().manual_seed(0)
    trace = [obs["policy"].clone()]
    for _ in range(steps):
        action = torch.rand(4, 21, generator=generator) * 2 - 1
        obs, reward, terminated, truncated, _ = env.step(action)
        trace += [obs["policy"].clone(), reward.clone(), terminated.clone()]
    env.close()
    SimulationContext.clear_instance()
    return trace


def test_lazy_forward_leaves_trajectories_unchanged():
    lazy, eager = run_humanoid(False), run_humanoid(True)
    assert any(t.dtype == torch.bool and t.any() for t in lazy)  # some episodes ended and reset
    for a, b in zip(lazy, eager):
        torch.testing.assert_close(a, b, rtol=0, atol=0)
