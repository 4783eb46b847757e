"""The shipped pretrained policies: ``simlab play --use_pretrained_checkpoint`` plays them at once and they balance."""

from __future__ import annotations

import math
import os

import pytest
import torch

from simlab.cli.main import build_parser
from simlab.cli.play import run_play
from simlab.pretrained import list_pretrained


def _pole_angle_counter():
    counts = {"inside": 0, "total": 0}

    def on_step(env, obs, actions) -> None:
        (robot,) = (a for a in env.scene.articulations.values() if "cart_to_pole" in a.joint_names)
        angle = robot.data.joint_pos[:, robot.joint_names.index("cart_to_pole")]
        angle = torch.remainder(angle + math.pi, 2 * math.pi) - math.pi
        counts["inside"] += int((angle.abs() < 0.2).sum())
        counts["total"] += angle.numel()

    return on_step, counts


@pytest.mark.parametrize(("task", "library"), list_pretrained())
def test_pretrained_policy_balances_the_pole(tmp_path, task, library):
    argv = ["play", "--task", task, "--library", library, "--use_pretrained_checkpoint", "--headless"]
    argv += ["--device", "cpu", "--num_envs", "64", "--steps", "300", "--log_root", str(tmp_path / "logs")]
    on_step, counts = _pole_angle_counter()
    result = run_play(build_parser().parse_args(argv), [], on_step=on_step)
    # the shipped files stay as they are: play copied the run to <log_root>/pretrained/<library>/<task name>
    assert result["checkpoint"].startswith(str(tmp_path / "logs" / "pretrained" / library))
    assert os.path.isfile(os.path.join(os.path.dirname(result["checkpoint"]), "exported", "policy.onnx"))
    assert counts["inside"] / counts["total"] >= 0.95  # the criterion of scripts/benchmarks/cartpole_learns.py
    argv[argv.index("--use_pretrained_checkpoint")] = "--use_last_checkpoint"
    with pytest.raises(FileNotFoundError):  # the copy is not taken for a training run of the user's
        run_play(build_parser().parse_args(argv), [])


def test_a_task_without_a_pretrained_policy_says_what_is_shipped(tmp_path, capsys):
    from simlab.cli.main import main

    argv = ["play", "--task", "simlab/Ant-Direct-v0", "--use_pretrained_checkpoint", "--device", "cpu"]
    assert main([*argv, "--log_root", str(tmp_path / "logs")]) == 2
    err = capsys.readouterr().err
    assert "No pretrained rsl_rl policy for simlab/Ant-Direct-v0" in err and "Shipped:" in err
