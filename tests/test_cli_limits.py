"""Settings and files at their limits get one line and exit 2, not a traceback (issue 37, items 6, 7, 9-11)."""

from __future__ import annotations

import os

import pytest

from simlab.cli.main import main

TASK = "simlab/Cartpole-v0"
SMALL = ["--task", TASK, "--num_envs", "8", "--headless", "--device", "cpu"]


def _run(tmp_path, *argv) -> int:
    return main([*argv, "--log_root", str(tmp_path / "logs")])


def _one_line_error(capsys) -> str:
    err = capsys.readouterr().err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    return err


# --- item 6: mini-batches that would be empty ----------------------------------------------------


@pytest.mark.parametrize(
    ("flags", "message"),
    [
        (
            ["agent.algorithm.num_mini_batches=1000"],
            "agent.algorithm.num_mini_batches=1000 leaves the mini-batches empty: a rollout holds 128 samples "
            "(8 envs x 16 steps). Use at most agent.algorithm.num_mini_batches=128",
        ),
        (
            ["--library", "skrl", "agent.agent.mini_batches=129"],
            "agent.agent.mini_batches=129 leaves the mini-batches empty: a rollout holds 128 samples "
            "(8 envs x 16 rollouts). Use at most agent.agent.mini_batches=128",
        ),
        (["--library", "sb3", "agent.batch_size=1"], "agent.batch_size=1 is too small: SB3's PPO normalizes"),
        (["--library", "sb3", "--num_envs", "1", "agent.n_steps=1"], "agent.n_steps=1 is too small"),
    ],
)
def test_empty_mini_batches_are_refused_before_training(tmp_path, capsys, flags, message):
    assert _run(tmp_path, "train", *SMALL, "--max_iterations", "1", *flags) == 2
    assert message in _one_line_error(capsys)
    assert not os.path.exists(tmp_path / "logs")


def test_the_largest_allowed_number_of_mini_batches_trains(tmp_path):
    argv = ["train", *SMALL, "--max_iterations", "1", "agent.algorithm.num_mini_batches=128"]
    assert _run(tmp_path, *argv) == 0
