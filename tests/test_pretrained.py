"""The shipped pretrained policies: ``simlab play --use_pretrained_checkpoint`` plays them at once on
the CPU and they meet their task's criterion (``simlab.benchmarks.criteria``)."""

from __future__ import annotations

import os

import pytest

from simlab.benchmarks.criteria import criterion_for
from simlab.cli.main import build_parser
from simlab.cli.play import run_play
from simlab.pretrained import list_pretrained, pretrained_record


@pytest.mark.parametrize(("task", "library"), list_pretrained())
def test_pretrained_policy_meets_its_criterion(tmp_path, task, library):
    record = pretrained_record(task, library)
    # the play make_pretrained.py judged on the CPU (the first cartpoles: 64 envs for 5 s)
    play = record["cpu_evaluation"] if record else {"envs": 64, "seconds": 5.0, "seed": 42}
    criterion = criterion_for(task, record.get("reward_threshold") if record else None)
    argv = ["play", "--task", task, "--library", library, "--use_pretrained_checkpoint", "--headless"]
    argv += ["--device", "cpu", "--num_envs", str(play["envs"]), "--seconds", str(play["seconds"])]
    argv += ["--seed", str(play["seed"])]
    argv += ["--log_root", str(tmp_path / "logs")]
    on_step, state = criterion.make_hook()
    result = run_play(build_parser().parse_args(argv), [], on_step=on_step)
    # the shipped files stay as they are: play copied the run to <log_root>/pretrained/<library>/<task name>
    assert result["checkpoint"].startswith(str(tmp_path / "logs" / "pretrained" / library))
    assert os.path.isfile(os.path.join(os.path.dirname(result["checkpoint"]), "exported", "policy.onnx"))
    score, passed = criterion.judge(result, state)
    assert passed, f"{task}: {criterion.description}: {score:.3f}"
    argv[argv.index("--use_pretrained_checkpoint")] = "--use_last_checkpoint"
    with pytest.raises(FileNotFoundError):  # the copy is not taken for a training run of the user's
        run_play(build_parser().parse_args(argv), [])


def test_a_task_without_a_pretrained_policy_says_what_is_shipped(tmp_path, capsys):
    from simlab.cli.main import main

    task = "simlab/Reach-Franka-v0"  # its rsl_rl policy ships, an skrl one does not
    argv = ["play", "--task", task, "--library", "skrl", "--use_pretrained_checkpoint", "--device", "cpu"]
    assert main([*argv, "--log_root", str(tmp_path / "logs")]) == 2
    err = capsys.readouterr().err
    assert f"No pretrained skrl policy for {task}" in err and "Shipped:" in err
    assert "Reach-Franka-v0 (rsl_rl)" in err


def test_a_play_variant_plays_the_policy_of_its_task(tmp_path):
    # Isaac Lab's play.py rule: Isaac-Reach-Franka-Play-v0 plays Isaac-Reach-Franka-v0's checkpoint
    argv = ["play", "--task", "simlab/Reach-Franka-Play-v0", "--use_pretrained_checkpoint", "--headless"]
    argv += ["--device", "cpu", "--num_envs", "2", "--steps", "3", "--log_root", str(tmp_path / "logs")]
    result = run_play(build_parser().parse_args(argv), [])
    assert result["checkpoint"].startswith(str(tmp_path / "logs" / "pretrained" / "rsl_rl" / "Reach-Franka-v0"))


def test_isaac_labs_pretrained_checkpoint_lookup_finds_the_shipped_policies(capsys):
    """Isaac Lab's play scripts call get_published_pretrained_checkpoint(workflow, task)."""
    import os

    from simlab.pretrained import PRETRAINED_DIR
    from simlab.utils.pretrained_checkpoint import get_published_pretrained_checkpoint, has_pretrained_checkpoint

    path = get_published_pretrained_checkpoint("rsl_rl", "Isaac-Cartpole-v0")
    assert path.startswith(PRETRAINED_DIR) and os.path.isfile(path) and path.endswith(".pt")
    assert has_pretrained_checkpoint("rsl_rl", "Isaac-Velocity-Rough-Unitree-Go2-Play-v0")  # the task's own
    assert get_published_pretrained_checkpoint("sb3", "Isaac-Cartpole-v0") is None
    assert "unavailable for this task. No pretrained sb3 policy for simlab/Cartpole-v0" in capsys.readouterr().out
