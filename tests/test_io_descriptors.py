"""IO descriptors: the YAML that tells a deployment what the policy reads and writes."""

from __future__ import annotations

import glob
import os

import gymnasium as gym
import pytest
import torch
import yaml

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.cli.main import main
from simlab.envs.utils.io_descriptors import generic_io_descriptor, record_shape
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.tasks.utils import parse_env_cfg


@pytest.fixture(scope="module")
def cartpole():
    cfg = parse_env_cfg("simlab/Cartpole-v0", device="cpu", num_envs=3)
    env = gym.make("simlab/Cartpole-v0", cfg=cfg).unwrapped
    yield env
    env.close()


def test_descriptors_follow_the_managers(cartpole, tmp_path):
    desc = cartpole.get_IO_descriptors
    obs = cartpole.observation_manager
    policy = desc["observations"]["policy"]
    assert [t["name"] for t in policy] == obs.active_terms["policy"]
    assert [tuple(t["shape"]) for t in policy] == [tuple(d) for d in obs.group_obs_term_dim["policy"]]
    # the terms' sizes add up to the policy's observation, the actions' to the action
    assert sum(t["shape"][0] for t in policy) == cartpole.observation_space["policy"].shape[-1]
    assert sum(a["shape"][0] for a in desc["actions"]) == cartpole.action_manager.total_action_dim
    robot = cartpole.scene["robot"]
    assert desc["articulations"]["robot"]["joint_names"] == robot.joint_names
    joint_pos = policy[0]
    assert joint_pos["observation_type"] == "JointState"
    assert joint_pos["joint_names"] == robot.joint_names
    assert joint_pos["joint_pos_offsets"] == robot.data.default_joint_pos[0].tolist()
    action = desc["actions"][0]
    term = cartpole.action_manager.get_term(action["name"])
    assert action["joint_names"] == term.joint_names and action["action_type"] == type(term).__name__
    assert desc["scene"] == {"physics_dt": cartpole.physics_dt, "dt": cartpole.step_dt, "decimation": 2}

    path = cartpole.export_IO_descriptors(str(tmp_path))
    assert os.path.basename(path) == "IO_descriptors.yaml"
    with open(path) as f:
        assert yaml.safe_load(f) == desc


def test_decorated_user_term_adds_fields_and_hooks(cartpole):
    @generic_io_descriptor(observation_type="Custom", units="m", on_inspect=[record_shape])
    def doubled_joint_pos(env):
        """Twice the joint positions."""
        return 2 * env.scene["robot"].data.joint_pos

    obs = cartpole.observation_manager
    obs._group_terms["policy"].append(("doubled", ObsTerm(func=doubled_joint_pos)))
    obs._group_obs_term_dim["policy"].append((2,))
    try:
        entry = cartpole.get_IO_descriptors["observations"]["policy"][-1]
    finally:
        obs._group_terms["policy"].pop()
        obs._group_obs_term_dim["policy"].pop()
    assert entry["observation_type"] == "Custom"
    assert entry["extras"]["units"] == "m"
    assert entry["description"] == "Twice the joint positions."
    assert entry["shape"] == [2] and entry["dtype"] == str(torch.float32)
    # the decorator marks the function and leaves it as it was: nothing added to the step
    assert doubled_joint_pos.__name__ == "doubled_joint_pos"


def test_export_without_folder_says_how(cartpole):
    cartpole.cfg.log_dir = None
    with pytest.raises(ValueError, match="log_dir"):
        cartpole.export_IO_descriptors()


def test_train_flag_writes_into_the_run(tmp_path, capsys):
    common = ["--num_envs", "4", "--headless", "--device", "cpu", "--max_iterations", "1"]
    logs = ["--log_root", str(tmp_path / "logs")]
    assert main(["train", "--task", "simlab/Cartpole-v0", *common, "--export_io_descriptors", *logs]) == 0
    (path,) = glob.glob(str(tmp_path / "logs" / "rsl_rl" / "*" / "*" / "io_descriptors" / "IO_descriptors.yaml"))
    with open(path) as f:
        assert [t["name"] for t in yaml.safe_load(f)["observations"]["policy"]] == ["joint_pos_rel", "joint_vel_rel"]

    assert main(["train", "--task", "simlab/Cartpole-Direct-v0", *common, "--export_io_descriptors", *logs]) == 0
    assert "direct task" in capsys.readouterr().out
    assert len(glob.glob(str(tmp_path / "logs" / "**" / "IO_descriptors.yaml"), recursive=True)) == 1
