"""The Crazyflie and the direct quadcopter task: mass, hover, roll sign, crash resets, training."""

from __future__ import annotations

import glob

import mujoco
import numpy as np
import pytest
import torch

from simlab.cli.main import main
from simlab.robots.quadcopter import CRAZYFLIE_CFG
from simlab.tasks.direct.quadcopter.quadcopter_env import QuadcopterEnv, QuadcopterEnvCfg
from simlab.tasks.utils import load_cfg_from_registry
from simlab.utils.math import euler_xyz_from_quat

NUM_ENVS = 4
HOVER_THRUST = 2.0 / 1.9 - 1.0  # thrust_to_weight * weight * (a + 1) / 2 == weight


@pytest.fixture(scope="module")
def env():
    cfg = QuadcopterEnvCfg(seed=0)
    cfg.scene.num_envs = NUM_ENVS
    cfg.sim.device = "cpu"
    env = QuadcopterEnv(cfg)
    yield env
    env.close()


def fresh_start(env) -> None:
    """Every env at its spawn pose with a full episode ahead (reset() spreads episode lengths)."""
    env.reset()
    env.episode_length_buf.zero_()


def actions(thrust: float = HOVER_THRUST, moment=(0.0, 0.0, 0.0)) -> torch.Tensor:
    return torch.tensor([[thrust, *moment]] * NUM_ENVS, dtype=torch.float32)


def test_crazyflie_model_has_published_mass_and_inertia():
    model = mujoco.MjModel.from_xml_path(CRAZYFLIE_CFG.spawn.asset_path)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    assert model.body_subtreemass[model.body("body").id] == pytest.approx(0.027)
    # the whole vehicle's inertia about its centre of mass, summed body by body (parallel axes)
    com = data.subtree_com[model.body("body").id]
    inertia = np.zeros((3, 3))
    for body in range(1, model.nbody):
        rot, offset = data.ximat[body].reshape(3, 3), data.xipos[body] - com
        inertia += rot @ np.diag(model.body_inertia[body]) @ rot.T
        inertia += model.body_mass[body] * (offset @ offset * np.eye(3) - np.outer(offset, offset))
    np.testing.assert_allclose(np.diag(inertia), [1.395e-5, 1.436e-5, 2.173e-5], rtol=1e-3)
    arm = np.linalg.norm(model.body("m1_prop").pos[:2])
    assert arm == pytest.approx(0.046, abs=1e-3)


def spin_under_full_moments(dt: float, decimation: int, steps: int = 15) -> tuple[torch.Tensor, int]:
    """|angular velocity| [rad/s] of drones at full thrust and full moments after ``steps`` env steps."""
    cfg = QuadcopterEnvCfg(seed=0)
    cfg.scene.num_envs = 2
    cfg.sim.device = "cpu"
    cfg.sim.dt, cfg.decimation = dt, decimation
    env = QuadcopterEnv(cfg)
    try:
        env.reset()
        env.episode_length_buf.zero_()
        full = torch.tensor([[1.0, 1.0, 1.0, 1.0], [1.0, 1.0, -1.0, 0.5]])
        for _ in range(steps):
            _, _, terminated, truncated, _ = env.step(full)
            assert not (terminated | truncated).any()
        return env._robot.data.root_ang_vel_w.norm(dim=1), env.sim.model.opt.integrator
    finally:
        env.close()


def test_spin_under_full_moments_follows_a_ten_times_finer_step():
    """Full moments (700 rad/s^2 on the 27 g drone) for 0.3 s: with the gyroscopic term left explicit
    (MuJoCo's implicitfast) the spin ran away to 1500 rad/s in 10 ms steps, and an exploring policy's
    rewards to -1e9, so training did not learn. CRAZYFLIE_CFG's enable_gyroscopic_forces selects the
    implicit integrator, which stays near a 1 ms step's 100-200 rad/s. (Runs before the module's env.)"""
    spin, integrator = spin_under_full_moments(dt=1 / 100, decimation=2)
    assert integrator == mujoco.mjtIntegrator.mjINT_IMPLICIT
    reference, _ = spin_under_full_moments(dt=1 / 1000, decimation=20)
    assert (reference > 90).all()  # spun up hard: the case that ran away
    # a tumbling body's spin drifts with the step size (1 ms implicitfast vs implicit: 15 %); the
    # runaway was 4x
    torch.testing.assert_close(spin, reference, rtol=0.3, atol=0.0)


def test_steps_with_finite_observations_of_width_12(env):
    fresh_start(env)
    torch.manual_seed(0)
    for _ in range(20):
        obs, reward, terminated, truncated, _ = env.step(2 * torch.rand(NUM_ENVS, 4) - 1)
        assert obs["policy"].shape == (NUM_ENVS, 12)
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
    assert env._robot.joint_names == ["m1_joint", "m2_joint", "m3_joint", "m4_joint"]
    assert env.graph_blockers() == []


def test_thrust_equal_to_weight_hovers_within_1cm_for_1s(env):
    fresh_start(env)
    start = env._robot.data.root_pos_w.clone()
    steps = round(1.0 / env.step_dt)
    for _ in range(steps):
        env.step(actions())
        drift = (env._robot.data.root_pos_w - start).norm(dim=1)
        assert drift.max() < 0.01, drift
    # and without thrust it falls: the hover is the thrust's doing
    fresh_start(env)
    for _ in range(10):
        env.step(actions(thrust=-1.0))
    assert (env._robot.data.root_pos_w[:, 2] < start[:, 2] - 0.05).all()


def test_positive_roll_moment_rolls_positively(env):
    fresh_start(env)
    for _ in range(10):
        obs, *_ = env.step(actions(moment=(0.02, 0.0, 0.0)))  # 0.2 mN m
    roll, pitch, _ = euler_xyz_from_quat(env._robot.data.root_quat_w, wrap_to_2pi=False)
    assert (roll > 0.05).all() and (pitch.abs() < 0.2 * roll).all(), (roll, pitch)
    assert (obs["policy"][:, 3] > 0).all()  # body-frame roll rate
    assert (obs["policy"][:, 7] < 0).all()  # gravity leans towards body -y when rolled about +x


def test_crashed_drone_ends_its_episode_and_resets_by_mask(env):
    fresh_start(env)
    spawn_height = env._robot.data.root_pos_w[:, 2].clone()
    drop = actions()
    drop[0, 0] = -1.0  # env 0 cuts its thrust, the others hover
    steps = 0
    terminated = torch.zeros(NUM_ENVS, dtype=torch.bool)
    while not terminated.any() and steps < 60:  # 0.4 m of free fall takes about 15 steps
        _, _, terminated, truncated, extras = env.step(drop)
        steps += 1
    assert terminated.tolist() == [True, False, False, False] and not truncated.any()
    assert extras["final_obs"]["policy"][0, 2] < 0  # falling when it ended
    assert env._robot.data.root_pos_w[0, 2] == pytest.approx(spawn_height[0].item(), abs=1e-5)
    assert env.episode_length_buf.tolist() == [0] + [steps] * (NUM_ENVS - 1)
    assert extras["log"]["Episode_Termination/died"].item() == 1.0
    assert env._robot.data.joint_vel[0].tolist() == pytest.approx([200.0, -200.0, 200.0, -200.0])


def test_agent_configs_are_isaac_labs():
    task = "simlab/Quadcopter-Direct-v0"
    rsl = load_cfg_from_registry(task, "rsl_rl_cfg_entry_point")
    rsl.to_rsl_rl_dict()  # no MISSING field left
    assert (rsl.num_steps_per_env, rsl.max_iterations, rsl.actor.hidden_dims) == (24, 200, [64, 64])
    skrl = load_cfg_from_registry(task, "skrl_cfg_entry_point")
    assert skrl["agent"]["rollouts"] == 24 and skrl["trainer"]["timesteps"] == 4800
    rl_games = load_cfg_from_registry(task, "rl_games_cfg_entry_point")
    assert rl_games["params"]["config"]["horizon_length"] == 24


def test_simlab_train_runs(tmp_path):
    argv = ["train", "--task", "simlab/Quadcopter-Direct-v0", "--num_envs", "8", "--max_iterations", "2",
            "--device", "cpu", "--headless", "--log_root", str(tmp_path / "logs")]  # fmt: skip
    assert main(argv) == 0
    assert glob.glob(str(tmp_path / "logs" / "rsl_rl" / "quadcopter_direct" / "*" / "model_*.pt"))
