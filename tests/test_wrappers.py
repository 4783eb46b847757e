"""The RL library wrappers on real simlab tasks (few envs, CPU)."""

from __future__ import annotations

import sys

import gymnasium as gym
import numpy as np
import pytest
import torch

from simlab.rl.utils import require
from simlab.tasks.utils import parse_env_cfg

NUM_ENVS = 4


def make(task="simlab/Cartpole-Direct-v0", episode_length_s=None, num_envs=NUM_ENVS):
    cfg = parse_env_cfg(task, device="cpu", num_envs=num_envs)
    if episode_length_s is not None:
        cfg.episode_length_s = episode_length_s
    return gym.make(task, cfg=cfg)


def test_missing_library_names_install_command(monkeypatch):
    monkeypatch.setitem(sys.modules, "skrl", None)  # import skrl -> ImportError
    with pytest.raises(ImportError, match=r'pip install "simlab\[skrl\]"'):
        require("skrl")


def test_rsl_rl_wrapper():
    from simlab.rl.rsl_rl import RslRlVecEnvWrapper

    env = RslRlVecEnvWrapper(make(episode_length_s=0.05), clip_actions=1.0)  # 3-step episodes
    try:
        obs = env.get_observations()
        assert list(obs.keys()) == ["policy"] and obs["policy"].shape == (NUM_ENVS, 4)
        assert env.num_actions == 1 and env.max_episode_length == 3
        assert env.unwrapped.single_action_space.high[0] == 1.0
        seen_time_out = False
        for _ in range(3):
            obs, rew, dones, extras = env.step(torch.full((NUM_ENVS, 1), 5.0))  # clipped to 1
            assert dones.dtype == torch.long and rew.shape == (NUM_ENVS,)
            # time-outs are flagged for bootstrapping; they are a subset of dones
            assert bool((dones.bool() | ~extras["time_outs"]).all())
            seen_time_out |= bool(extras["time_outs"].any())
            assert torch.equal(obs["policy"], env.get_observations()["policy"])
        assert seen_time_out
    finally:
        env.close()


def test_rsl_rl_training_computes_the_observations_once_per_step_and_play_keeps_final_obs(tmp_path):
    """rsl_rl never reads ``extras["final_obs"]``: ``simlab train`` spares its env the second observation
    pass before each step's resets (for the rough G1 a second height scan). The wrapper itself keeps them:
    play's success criteria (navigation, the cabinet) read the final observations."""
    from simlab.cli.main import build_parser
    from simlab.cli.train import run_train
    from simlab.rl.rsl_rl import RslRlVecEnvWrapper
    from simlab.utils.io import load_yaml

    env = RslRlVecEnvWrapper(make("simlab/Cartpole-v0", episode_length_s=0.05))  # 3-step episodes
    try:
        finals = [("final_obs" in env.step(torch.zeros(NUM_ENVS, 1))[3]) for _ in range(4)]  # crosses a time-out
        assert any(finals)
    finally:
        env.close()

    argv = ["train", "--task", "simlab/Cartpole-v0", "--headless", "--device", "cpu", "--num_envs", "8"]
    run_dir = run_train(build_parser().parse_args(argv + ["--max_iterations", "1", "--log_root", str(tmp_path)]), [])
    assert load_yaml(f"{run_dir}/params/env.yaml")["final_observations"] is False


def test_rsl_rl_wrapper_rejects_multi_agent():
    from simlab.rl.rsl_rl import RslRlVecEnvWrapper

    env = make("simlab/Cart-Double-Pendulum-Direct-v0", num_envs=2)
    try:
        with pytest.raises(ValueError, match="multi_agent_to_single_agent"):
            RslRlVecEnvWrapper(env)
    finally:
        env.close()


def test_skrl_wrapper_single_and_multi_agent():
    from simlab.rl.skrl import SkrlVecEnvWrapper

    env = SkrlVecEnvWrapper(make(), ml_framework="torch")
    try:
        obs, _ = env.reset()
        assert obs.shape == (NUM_ENVS, 4) and env.num_envs == NUM_ENVS
        obs, rew, term, trunc, info = env.step(torch.zeros(NUM_ENVS, 1))
        assert rew.shape == term.shape == trunc.shape == (NUM_ENVS, 1)
    finally:
        env.close()
    with pytest.raises(ValueError, match="Unknown skrl wrapper"):
        SkrlVecEnvWrapper(make(), wrapper="gym")

    env = SkrlVecEnvWrapper(make("simlab/Cart-Double-Pendulum-Direct-v0", num_envs=2), wrapper="auto")
    try:
        assert env.possible_agents == ["cart", "pendulum"]
        obs, _ = env.reset()
        assert obs["cart"].shape == (2, 4) and obs["pendulum"].shape == (2, 3)
        state = env.state()
        assert state["cart"].shape == (2, 7)  # the shared state: both observations
        _, rew, term, _, _ = env.step({"cart": torch.zeros(2, 1), "pendulum": torch.zeros(2, 1)})
        assert rew["cart"].shape == (2, 1)
    finally:
        env.close()


def test_sb3_wrapper_terminal_observation_and_episode_info():
    from simlab.rl.sb3 import Sb3VecEnvWrapper

    env = Sb3VecEnvWrapper(make(episode_length_s=0.05))  # time-out after 3 steps
    try:
        obs = env.reset()
        assert isinstance(obs, np.ndarray) and obs.shape == (NUM_ENVS, 4)
        assert np.isfinite(env.action_space.high).all()  # SB3 needs finite bounds
        total = np.zeros(NUM_ENVS)
        length = np.zeros(NUM_ENVS)
        checked = 0
        for _ in range(4):
            env.step_async(np.zeros((NUM_ENVS, 1), dtype=np.float32))
            obs, rew, dones, infos = env.step_wait()
            total += rew
            length += 1
            final = env.unwrapped.extras["final_obs"]["policy"].numpy()
            truncated = env.unwrapped.reset_time_outs.numpy()
            for i in np.flatnonzero(dones):
                info = infos[i]
                assert info["TimeLimit.truncated"] == bool(truncated[i])
                np.testing.assert_allclose(info["terminal_observation"], final[i])
                # the returned observation is the reset one, not the terminal one
                assert not np.allclose(obs[i], final[i])
                assert info["episode"]["l"] == length[i]
                assert info["episode"]["r"] == pytest.approx(total[i], rel=1e-5)
                total[i] = length[i] = 0
                checked += 1
            for i in np.flatnonzero(~dones):
                assert infos[i] == {} or set(infos[i]) == {"log"}
        assert checked >= NUM_ENVS
    finally:
        env.close()


def test_process_sb3_cfg():
    from simlab.rl.sb3 import process_sb3_cfg

    out = process_sb3_cfg(
        {
            "n_steps": 16,
            "n_minibatches": 4,
            "learning_rate": "lin_1e-3",
            "policy_kwargs": {"activation_fn": "nn.ELU", "net_arch": [32, 32]},
        },
        num_envs=8,
    )
    assert out["batch_size"] == 32 and "n_minibatches" not in out
    assert out["policy_kwargs"]["activation_fn"] is torch.nn.ELU
    assert out["learning_rate"](0.5) == pytest.approx(5e-4)
    with pytest.raises(ValueError, match="Foo"):
        process_sb3_cfg({"policy_kwargs": {"activation_fn": "nn.Foo"}}, 1)


def test_rl_games_wrapper():
    from simlab.rl.rl_games import RlGamesVecEnvWrapper

    env = RlGamesVecEnvWrapper(
        make(), "cpu", clip_obs=0.01, clip_actions=1.0, obs_groups={"obs": ["policy"], "states": ["policy"]}
    )
    try:
        info = env.get_env_info()
        assert info["observation_space"].shape == (4,) and info["state_space"].shape == (4,)
        assert info["action_space"].high[0] == 1.0
        obs = env.reset()
        assert set(obs) == {"obs", "states"} and obs["obs"].abs().max() <= 0.01
        obs, rew, dones, extras = env.step(torch.zeros(NUM_ENVS, 1))
        assert rew.shape == (NUM_ENVS,) and "time_outs" in extras
    finally:
        env.close()
    with pytest.raises(ValueError, match="not groups of the env"):
        RlGamesVecEnvWrapper(make(), "cpu", 5.0, 1.0, obs_groups={"obs": ["critic"]})


def test_progress_logger_keeps_rsl_rl_episode_statistics(tmp_path):
    """simlab's rsl_rl logger defers the episode bookkeeping to log time; the buffers must match rsl_rl's."""
    from rsl_rl.utils.logger import Logger

    from simlab.cli.libraries.rsl_rl import _ProgressLogger

    cfg = {"num_steps_per_env": 4, "algorithm": {}, "logger": "tensorboard"}
    args = {"cfg": cfg, "env_cfg": {}, "num_envs": 6, "is_distributed": False, "gpu_world_size": 1,
            "gpu_global_rank": 0, "device": "cpu"}  # fmt: skip
    ours, theirs = _ProgressLogger(log_dir=str(tmp_path / "a"), **args), Logger(log_dir=str(tmp_path / "b"), **args)
    ours.writer = theirs.writer = object()  # bookkeeping runs only with a writer
    generator = torch.Generator().manual_seed(0)
    for _ in range(40):
        rewards = torch.rand(6, generator=generator)
        dones = (torch.rand(6, generator=generator) < 0.2).float()
        ours.process_env_step(rewards, dones, {})
        theirs.process_env_step(rewards, dones, {})
    ours._flush_finished()
    assert len(theirs.rewbuffer) > 10
    assert list(ours.rewbuffer) == pytest.approx(list(theirs.rewbuffer))
    assert list(ours.lenbuffer) == list(theirs.lenbuffer)
    torch.testing.assert_close(ours.cur_reward_sum, theirs.cur_reward_sum)
