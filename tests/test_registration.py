"""Task registration, configs from the registry, checkpoint lookup."""

from __future__ import annotations

import os
import time

import gymnasium as gym
import pytest
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.tasks.utils import get_checkpoint_path, load_cfg_from_registry, parse_env_cfg, registered_task_ids

TASKS = [
    "simlab/Cartpole-v0",
    "simlab/Cartpole-Direct-v0",
    "simlab/Humanoid-Direct-v0",
    "simlab/Ant-Direct-v0",
    "simlab/Cart-Double-Pendulum-Direct-v0",
]
AGENT_KEYS = ["rsl_rl_cfg_entry_point", "skrl_cfg_entry_point", "sb3_cfg_entry_point", "rl_games_cfg_entry_point"]


def test_every_task_is_registered_with_all_entry_points():
    assert set(TASKS) <= set(registered_task_ids())
    for task in TASKS:
        spec = gym.spec(task)
        assert spec.disable_env_checker
        for key in ["env_cfg_entry_point", *AGENT_KEYS]:
            assert key in spec.kwargs, (task, key)
    marl = gym.spec("simlab/Cart-Double-Pendulum-Direct-v0").kwargs
    assert "skrl_ippo_cfg_entry_point" in marl and "skrl_mappo_cfg_entry_point" in marl


@pytest.mark.parametrize("task", TASKS)
def test_agent_configs_load(task):
    rsl = load_cfg_from_registry(task, "rsl_rl_cfg_entry_point")
    rsl.to_rsl_rl_dict()  # validates: no MISSING field left
    assert rsl.max_iterations > 0 and rsl.num_steps_per_env > 0
    skrl = load_cfg_from_registry(task, "skrl_cfg_entry_point")
    assert skrl["agent"]["class"] == "PPO" and skrl["trainer"]["timesteps"] > 0
    sb3 = load_cfg_from_registry(task, "sb3_cfg_entry_point")
    assert sb3["policy"] == "MlpPolicy" and sb3["n_timesteps"] > 0
    rlg = load_cfg_from_registry(task, "rl_games_cfg_entry_point")
    assert rlg["params"]["config"]["torch_compile"] is False  # on by default in rl_games; needs a compiler
    assert rlg["params"]["algo"]["name"] == "a2c_continuous"


def test_multi_agent_skrl_configs():
    task = "simlab/Cart-Double-Pendulum-Direct-v0"
    assert load_cfg_from_registry(task, "skrl_ippo_cfg_entry_point")["agent"]["class"] == "IPPO"
    mappo = load_cfg_from_registry(task, "skrl_mappo_cfg_entry_point")
    assert mappo["agent"]["class"] == "MAPPO"
    assert mappo["models"]["value"]["network"][0]["input"] == "STATES"  # centralized critic


def test_cartpole_hyperparameters_follow_isaac_lab():
    rsl = load_cfg_from_registry("simlab/Cartpole-v0", "rsl_rl_cfg_entry_point")
    assert (rsl.num_steps_per_env, rsl.max_iterations, rsl.experiment_name) == (16, 150, "cartpole")
    assert rsl.actor.hidden_dims == [32, 32] and rsl.algorithm.learning_rate == 1.0e-3


@pytest.mark.parametrize("task", ["simlab/Cartpole-v0", "simlab/Cartpole-Direct-v0"])
def test_gym_make_with_cfg(task):
    cfg = parse_env_cfg(task, device="cpu", num_envs=2)
    assert cfg.scene.num_envs == 2 and cfg.sim.device == "cpu"
    env = gym.make(task, cfg=cfg, render_mode="rgb_array")
    try:
        obs, extras = env.reset()
        assert obs["policy"].shape == (2, 4)
        obs, rew, term, trunc, extras = env.step(torch.zeros(2, 1))
        assert rew.shape == (2,) and term.dtype == torch.bool
        assert env.render_mode == "rgb_array"
    finally:
        env.close()


def test_unknown_task_names_closest():
    with pytest.raises(ValueError, match="Cartpole-v0") as e:
        load_cfg_from_registry("simlab/Cartpol-v0", "env_cfg_entry_point")
    assert "Closest" in str(e.value)
    # the closest ids and `simlab list`, not every registered id (a line of thousands of characters)
    assert "simlab list" in str(e.value) and "simlab/Velocity-Rough-Unitree-Go2-v0" not in str(e.value)
    assert str(e.value).endswith("the Isaac Lab tasks simlab lacks, and why, are in docs/task_families.md.")
    with pytest.raises(ValueError, match="simlab's is 'simlab/Velocity-Flat-Unitree-Go2-v0'"):
        load_cfg_from_registry("Isaac-Velocity-Flat-Unitree-Go2-v0", "env_cfg_entry_point")


def test_missing_entry_point_lists_available():
    with pytest.raises(ValueError, match="rsl_rl_cfg_entry_point"):
        load_cfg_from_registry("simlab/Cartpole-v0", "rsl_rl_cfg_entry")


def test_parse_env_cfg_rejects_bad_num_envs():
    with pytest.raises(ValueError, match="num_envs"):
        parse_env_cfg("simlab/Cartpole-v0", device="cpu", num_envs=0)


def test_get_checkpoint_path(tmp_path):
    for run in ("2026-01-01_10-00-00", "2026-01-02_10-00-00"):
        os.makedirs(tmp_path / run)
        for it in (9, 10, 100):
            (tmp_path / run / f"model_{it}.pt").write_text("x")
            time.sleep(0.001)
    path = get_checkpoint_path(str(tmp_path), ".*", r"model_\d+\.pt")
    assert path.endswith(os.path.join("2026-01-02_10-00-00", "model_100.pt"))  # natural order: 100 > 10 > 9
    assert get_checkpoint_path(str(tmp_path), "2026-01-01.*", r"model_9\.pt").endswith("model_9.pt")
    with pytest.raises(FileNotFoundError, match="Looked in"):
        get_checkpoint_path(str(tmp_path), ".*", r"agent_\d+\.pt")
    with pytest.raises(FileNotFoundError, match="does not exist"):
        get_checkpoint_path(str(tmp_path / "nope"))
