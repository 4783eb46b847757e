"""``--export_io_descriptors``: Isaac Lab's IO descriptor YAML of a manager-based task, checked against
its observation and action terms; direct tasks say they have none."""

from __future__ import annotations

import glob
import os

import gymnasium as gym
import yaml

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.cli.main import main
from simlab.envs import mdp
from simlab.managers import ObservationTermCfg
from simlab.tasks.utils import load_cfg_from_registry

TASK = "simlab/Cartpole-v0"


def test_descriptors_match_the_observation_and_action_terms(tmp_path):
    cfg = load_cfg_from_registry(TASK, "env_cfg_entry_point")
    cfg.scene.num_envs = 2
    cfg.sim.device = "cpu"
    cfg.observations.policy.last_action = ObservationTermCfg(func=mdp.last_action, scale=2.0, clip=(-5.0, 5.0))
    cfg.log_dir = str(tmp_path)
    cfg.export_io_descriptors = True
    env = gym.make(TASK, cfg=cfg)
    try:
        base = env.unwrapped
        with open(tmp_path / "io_descriptors" / "IO_descriptors.yaml") as f:
            written = yaml.safe_load(f)
        assert written == yaml.safe_load(yaml.safe_dump(base.get_IO_descriptors))

        policy = written["observations"]["policy"]
        assert [t["term_name"] for t in policy] == base.observation_manager.active_terms["policy"]
        assert sum(t["shape"][0] for t in policy) == base.observation_manager.group_obs_dim["policy"][0] == 5
        pos = policy[0]
        assert (pos["name"], pos["observation_type"], pos["extras"]["units"]) == ("joint_pos_rel", "JointState", "rad")
        assert pos["joint_names"] == base.scene["robot"].joint_names and pos["joint_pos_offsets"] == [0.0, 0.0]
        action = policy[2]
        assert (action["name"], action["observation_type"]) == ("last_action", "Action")
        assert action["overloads"]["scale"] == 2.0 and action["overloads"]["clip"] == [-5.0, 5.0]

        (effort,) = written["actions"]
        assert effort["shape"] == [base.action_manager.total_action_dim] == [1]
        assert (effort["action_type"], effort["joint_names"], effort["scale"]) == (
            "JointAction",
            ["slider_to_cart"],
            100.0,
        )
        assert written["articulations"]["robot"]["joint_names"] == ["slider_to_cart", "cart_to_pole"]
        assert written["scene"] == {"physics_dt": base.physics_dt, "dt": base.step_dt, "decimation": 2}
    finally:
        env.close()


def test_train_flag_writes_them_into_the_run_folder_and_direct_tasks_say_they_have_none(tmp_path, capsys):
    small = ["--num_envs", "4", "--headless", "--device", "cpu", "--max_iterations", "1"]
    logs = ["--log_root", str(tmp_path / "logs")]
    assert main(["train", "--task", TASK, *small, *logs, "--export_io_descriptors"]) == 0
    (path,) = glob.glob(str(tmp_path / "logs" / "rsl_rl" / "*" / "*" / "io_descriptors" / "IO_descriptors.yaml"))
    with open(path) as f:
        assert [t["term_name"] for t in yaml.safe_load(f)["observations"]["policy"]] == [
            "joint_pos_rel",
            "joint_vel_rel",
        ]

    capsys.readouterr()
    assert main(["train", "--task", "simlab/Cartpole-Direct-v0", *small, *logs, "--export_io_descriptors"]) == 0
    assert "is a direct task, which has no observation or action terms" in capsys.readouterr().out
    assert not glob.glob(str(tmp_path / "logs" / "rsl_rl" / "cartpole_direct" / "*" / "io_descriptors"))
    assert os.path.isdir(str(tmp_path / "logs" / "rsl_rl"))
