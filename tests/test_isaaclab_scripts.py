"""Isaac Lab's ``scripts/reinforcement_learning/<library>/{train,play}.py`` on simlab, as the tutorials run them."""

from __future__ import annotations

import glob
import os
import subprocess
import sys

import pytest

from simlab.cli.isaaclab_scripts import build_script_parser, script_to_simlab_argv

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CPU = ["--headless", "--device", "cpu"]


def _script(tmp_path, library: str, mode: str, *argv: str) -> subprocess.CompletedProcess:
    script = os.path.join(REPO, "scripts", "reinforcement_learning", library, f"{mode}.py")
    env = dict(os.environ, PYTHONPATH=REPO, OMP_NUM_THREADS="1")
    return subprocess.run(
        [sys.executable, script, *argv], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300
    )


@pytest.mark.slow  # four fresh processes; the rsl_rl script's run below keeps the scripts in the default set
@pytest.mark.parametrize(
    ("library", "train_args"),
    [("skrl", ["--max_iterations", "2", "agent.agent.rollouts=8"]), ("sb3", ["--max_iterations", "2"])],
)
def test_tutorial_train_and_play_commands_run(tmp_path, library, train_args):
    done = _script(tmp_path, library, "train", "--task", "Isaac-Cartpole-v0", "--num_envs", "8", *CPU, *train_args)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    assert "Isaac-Cartpole-v0 -> simlab/Cartpole-v0" in done.stdout
    runs = glob.glob(str(tmp_path / "logs" / library / "*" / "*"))
    assert len(runs) == 1  # Isaac Lab's log layout: ./logs/<library>/<experiment>/<run>
    played = _script(tmp_path, library, "play", "--task", "Isaac-Cartpole-v0", "--num_envs", "4", *CPU,
                     "--max_app_steps", "5")  # fmt: skip
    assert played.returncode == 0, played.stdout[-2000:] + played.stderr[-2000:]
    assert "Playing" in played.stdout and glob.glob(os.path.join(runs[0], "**", "policy.onnx"), recursive=True)


@pytest.mark.parametrize("library", [pytest.param("skrl", marks=pytest.mark.slow), "sb3"])
def test_tutorial_play_with_the_pretrained_checkpoint(tmp_path, library):
    """Isaac Lab's ``<library>/play.py --task Isaac-Cartpole-v0 --use_pretrained_checkpoint`` plays the
    cartpole policy shipped for that library (simlab/pretrained/Cartpole-v0/<library>/)."""
    played = _script(tmp_path, library, "play", "--task", "Isaac-Cartpole-v0", "--num_envs", "4", *CPU,
                     "--use_pretrained_checkpoint", "--max_app_steps", "5")  # fmt: skip
    assert played.returncode == 0, played.stdout[-2000:] + played.stderr[-2000:]
    copied = tmp_path / "logs" / "pretrained" / library / "Cartpole-v0"
    assert f"Playing {copied}" in played.stdout
    assert glob.glob(str(copied / "**" / "exported" / "policy.onnx"), recursive=True)


def test_rsl_rl_resume_flags_find_the_checkpoint(tmp_path):
    first = _script(tmp_path, "rsl_rl", "train", "--task", "simlab/Cartpole-v0", "--num_envs", "8", *CPU,
                    "--max_iterations", "2", "--run_name", "first", "agent.save_interval=1")  # fmt: skip
    assert first.returncode == 0, first.stdout[-2000:] + first.stderr[-2000:]
    resume = ["--resume", "--load_run", ".*_first", "--checkpoint", "model_1.pt"]
    resumed = _script(tmp_path, "rsl_rl", "train", "--task", "simlab/Cartpole-v0", "--num_envs", "8", *CPU,
                      "--max_iterations", "1", *resume)  # fmt: skip
    assert resumed.returncode == 0, resumed.stdout[-2000:] + resumed.stderr[-2000:]
    assert "_first/model_1.pt at iteration 1" in resumed.stdout


def test_flags_map_to_simlab_and_unsupported_ones_say_so(capsys):
    args, rest = build_script_parser("skrl", "train").parse_known_args(
        ["--task", "Isaac-Cartpole-v0", "--seed", "3", "--ml_framework", "jax", "--distributed", "agent.seed=1"]
    )
    argv = script_to_simlab_argv("skrl", "train", args, rest)
    assert argv[:3] == ["train", "--task", "simlab/Cartpole-v0"]
    assert {"--ml_framework", "jax", "--distributed", "--seed", "3"} <= set(argv) and argv[-1] == "agent.seed=1"
    args, rest = build_script_parser("skrl", "play").parse_known_args(["--task", "T", "--use_pretrained_checkpoint"])
    argv = script_to_simlab_argv("skrl", "play", args, rest)
    assert "--use_pretrained_checkpoint" in argv and "--use_last_checkpoint" not in argv
    args, rest = build_script_parser("skrl", "train").parse_known_args(
        ["--task", "Isaac-Humanoid-AMP-Walk-Direct-v0", "--algorithm", "AMP"]
    )
    argv = script_to_simlab_argv("skrl", "train", args, rest)
    assert argv[2] == "simlab/Humanoid-AMP-Walk-Direct-v0" and argv[argv.index("--algorithm") + 1] == "AMP"
    args, rest = build_script_parser("rsl_rl", "train").parse_known_args(["--task", "T", "--export_io_descriptors"])
    assert "--export_io_descriptors" in script_to_simlab_argv("rsl_rl", "train", args, rest)
    args, rest = build_script_parser("rl_games", "train").parse_known_args(["--task", "T", "--sigma", "0.5"])
    script_to_simlab_argv("rl_games", "train", args, rest)
    assert "--sigma has no effect" in capsys.readouterr().out
    with pytest.raises(SystemExit):  # SB3 has no multi-process training: no --distributed, as in Isaac Lab
        build_script_parser("sb3", "train").parse_args(["--task", "T", "--distributed"])
