"""The shipped pretrained policies: ``simlab play --use_pretrained_checkpoint`` plays them at once and they balance."""

from __future__ import annotations

import os

import pytest

from simlab.benchmarks.criteria import pole_angle_tracker
from simlab.cli.main import build_parser
from simlab.cli.play import run_play
from simlab.pretrained import list_pretrained


@pytest.mark.parametrize(("task", "library"), list_pretrained())
def test_pretrained_policy_balances_the_pole(tmp_path, task, library):
    argv = ["play", "--task", task, "--library", library, "--use_pretrained_checkpoint", "--headless"]
    argv += ["--device", "cpu", "--num_envs", "64", "--steps", "300", "--log_root", str(tmp_path / "logs")]
    on_step, counts = pole_angle_tracker(0.2)
    result = run_play(build_parser().parse_args(argv), [], on_step=on_step)
    # the shipped files stay as they are: play copied the run to <log_root>/pretrained/<library>/<task name>
    assert result["checkpoint"].startswith(str(tmp_path / "logs" / "pretrained" / library))
    assert os.path.isfile(os.path.join(os.path.dirname(result["checkpoint"]), "exported", "policy.onnx"))
    assert counts["inside"] / counts["total"] >= 0.95  # the criterion of simlab bench solve
    argv[argv.index("--use_pretrained_checkpoint")] = "--use_last_checkpoint"
    with pytest.raises(FileNotFoundError):  # the copy is not taken for a training run of the user's
        run_play(build_parser().parse_args(argv), [])


def test_a_task_without_a_pretrained_policy_says_what_is_shipped(tmp_path, capsys):
    from simlab.cli.main import main

    argv = ["play", "--task", "simlab/Ant-Direct-v0", "--use_pretrained_checkpoint", "--device", "cpu"]
    assert main([*argv, "--log_root", str(tmp_path / "logs")]) == 2
    err = capsys.readouterr().err
    assert "No pretrained rsl_rl policy for simlab/Ant-Direct-v0" in err and "Shipped:" in err
