"""The direct ANYmal-C velocity tasks (issue 41.2): simlab's own (``simlab.tasks.direct.anymal_c``) builds,
steps and is judged on its own command buffer, and Isaac Lab's task files
(``tests/ported/isaaclab_anymal_c_direct``, its release 2.x text with the import mapping applied) run
on simlab and walk the same trajectories under the same actions."""

from __future__ import annotations

import sys
from pathlib import Path

import gymnasium as gym
import pytest
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.tasks.direct.anymal_c.anymal_c_env import AnymalCEnv, AnymalCFlatEnvCfg, AnymalCRoughEnvCfg
from simlab.tasks.manager_based.locomotion.velocity import criterion as velocity_criterion
from simlab.tasks.utils.criteria import criterion_for
from simlab.tasks.utils.parse_cfg import parse_env_cfg

N = 3
SCAN = 17 * 11
PORTED = Path(__file__).parent / "ported"


@pytest.mark.parametrize(("terrain", "obs_dim"), [("Flat", 48), ("Rough", 48 + SCAN)])
def test_direct_anymal_c_builds_steps_and_is_judged_on_its_own_commands(terrain, obs_dim):
    task = f"simlab/Velocity-{terrain}-Anymal-C-Direct-v0"
    criterion = criterion_for(task)
    assert criterion.description == velocity_criterion.tracks_velocity().description
    cfg = parse_env_cfg(task, device="cpu", num_envs=N)
    cfg.seed = 0
    env = gym.make(task, cfg=cfg).unwrapped
    try:
        obs, _ = env.reset()
        assert obs["policy"].shape == (N, obs_dim)
        assert env.graph_blockers() == [], "the step can be captured as a CUDA graph"
        assert ((env._commands >= -1.0) & (env._commands <= 1.0)).all()
        on_step, sums = criterion.make_hook()
        for _ in range(20):
            actions = 0.3 * torch.randn(N, 12)
            obs, reward, terminated, truncated, extras = env.step(actions)
            assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
            on_step(env, obs, actions)
        # the hook read this task's commands: the mean error is that of the commands against the base velocity
        assert sums["total"] == 20 * N and 0.0 < sums["error"] / sums["total"] < 3.0
        assert "Episode_Reward/track_lin_vel_xy_exp" in extras["log"]
    finally:
        env.close()


@pytest.mark.parametrize("terrain", ["Flat", "Rough"])
def test_isaac_labs_own_direct_task_walks_as_simlabs(terrain):
    sys.path.insert(0, str(PORTED))
    try:
        from isaaclab_anymal_c_direct import anymal_c_env as ported
    finally:
        sys.path.remove(str(PORTED))
    ours_cfg_class = {"Flat": AnymalCFlatEnvCfg, "Rough": AnymalCRoughEnvCfg}[terrain]
    theirs_cfg_class = getattr(ported, f"AnymalC{terrain}EnvCfg")
    observations, resets = [], []
    for env_class, cfg_class in ((AnymalCEnv, ours_cfg_class), (ported.AnymalCEnv, theirs_cfg_class)):
        cfg = cfg_class(seed=0)
        cfg.scene.num_envs, cfg.sim.device = N, "cpu"
        env = env_class(cfg)
        try:
            torch.manual_seed(1)
            actions = 0.3 * torch.randn(10, N, 12)
            obs, _ = env.reset(seed=0)
            trajectory, reset = [obs["policy"]], torch.zeros(N, dtype=torch.bool)
            for step in range(10):
                obs, reward, terminated, truncated, extras = env.step(actions[step])
                assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
                trajectory.append(obs["policy"])
                reset |= terminated | truncated
            observations.append(torch.stack(trajectory))
            resets.append(reset)
        finally:
            env.close()
    assert observations[0].shape == (11, N, 48 + (SCAN if terrain == "Rough" else 0))
    # a reset draws new commands: simlab's task draws them for all envs and keeps the reset ones', Isaac
    # Lab's for the reset envs only, so the random streams part after the first reset of some envs
    torch.testing.assert_close(resets[0], resets[1])
    kept = ~resets[0]
    assert kept.any()
    torch.testing.assert_close(observations[0][:, kept], observations[1][:, kept])


def test_the_direct_flat_task_observes_and_acts_as_the_manager_based_one():
    """The shipped direct flat policy started from the manager-based one (docs/locomotion.md); that holds
    while the direct task reads a state as the manager task does, term for term and joint for joint,
    and turns actions into the same joint targets on the same drives at the same rate."""
    from types import SimpleNamespace

    cfg = parse_env_cfg("simlab/Velocity-Flat-Anymal-C-v0", device="cpu", num_envs=N)
    cfg.seed, cfg.observations.policy.enable_corruption = 0, False  # noise-free: the direct task has none
    env = gym.make("simlab/Velocity-Flat-Anymal-C-v0", cfg=cfg).unwrapped
    try:
        env.reset()
        for _ in range(5):
            env.step(0.3 * torch.randn(N, 12))
        robot = env.scene["robot"]
        command = env.command_manager.get_command("base_velocity")
        state = SimpleNamespace(
            _robot=robot, _commands=command, _actions=env.action_manager.action, _height_scanner=None
        )
        direct = AnymalCEnv._get_observations(state)["policy"]
        torch.testing.assert_close(direct, env.observation_manager.compute()["policy"])
        direct_cfg = AnymalCFlatEnvCfg()
        term = env.action_manager.get_term("joint_pos")
        assert term.cfg.scale == direct_cfg.action_scale and term.cfg.use_default_offset
        assert direct_cfg.robot.actuators["legs"] == cfg.scene.robot.actuators["legs"]
        assert (direct_cfg.sim.dt, direct_cfg.decimation) == (cfg.sim.dt, cfg.decimation)
    finally:
        env.close()
