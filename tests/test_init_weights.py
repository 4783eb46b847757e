"""``simlab train --init_weights``: a new run whose networks start from a checkpoint's weights, which may
come from another task of the same sizes (fine-tuning a shipped policy on a sibling task); a checkpoint
that does not fit is refused in one line."""

from __future__ import annotations

import glob
import os

import pytest
import torch

from simlab.cli.main import main
from simlab.pretrained import unpack_pretrained_checkpoint
from simlab.utils.io import load_yaml

MANAGER, DIRECT = "simlab/Cartpole-v0", "simlab/Cartpole-Direct-v0"
# learning rate 0: the weights a run saves are the weights it started from
FROZEN = ["agent.algorithm.learning_rate=0.0", "agent.algorithm.schedule=fixed"]


def _train(tmp_path, task: str, *extra: str, iterations: int = 1) -> int:
    argv = ["train", "--task", task, "--num_envs", "8", "--headless", "--device", "cpu"]
    return main([*argv, "--max_iterations", str(iterations), "--log_root", str(tmp_path / "logs"), *extra])


def _saved(tmp_path, experiment: str) -> dict:
    (path,) = glob.glob(str(tmp_path / "logs" / "rsl_rl" / experiment / "*" / "model_0.pt"))
    return torch.load(path, map_location="cpu", weights_only=True) | {"path": path}


def _same(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(torch.equal(a[k], b[k]) for k in a)


def test_a_run_starts_from_another_tasks_weights_at_iteration_zero(tmp_path, capsys):
    # the shipped manager-based cartpole policy (its actor only) starts a run of the direct task
    shipped = unpack_pretrained_checkpoint(MANAGER, "rsl_rl", str(tmp_path / "shipped"))
    assert _train(tmp_path, DIRECT, "--init_weights", shipped, *FROZEN) == 0
    assert "Initialized the actor (the critic starts untrained)" in capsys.readouterr().out
    run = _saved(tmp_path, "cartpole_direct")
    assert run["iter"] == 0  # a new run: its own iteration count, not the checkpoint's
    assert _same(run["actor_state_dict"], torch.load(shipped, weights_only=True)["actor_state_dict"])
    info = load_yaml(os.path.join(os.path.dirname(run["path"]), "params", "run.yaml"))
    assert info["task"] == DIRECT and info["init_weights"] == shipped

    # a checkpoint with a critic gives both networks
    assert _train(tmp_path, MANAGER, "--init_weights", run["path"], *FROZEN) == 0
    assert "Initialized the actor and critic" in capsys.readouterr().out
    again = _saved(tmp_path, "cartpole")
    assert _same(again["actor_state_dict"], run["actor_state_dict"])
    assert _same(again["critic_state_dict"], run["critic_state_dict"])


def test_warmup_critic_keeps_the_given_actor_for_its_iterations_then_trains_it(tmp_path, capsys):
    shipped = unpack_pretrained_checkpoint(MANAGER, "rsl_rl", str(tmp_path / "shipped"))
    given = torch.load(shipped, weights_only=True)["actor_state_dict"]
    argv = ["--init_weights", shipped, "--warmup_critic", "1", "agent.save_interval=1"]
    assert _train(tmp_path, DIRECT, *argv, iterations=2) == 0
    assert "The first 1 iterations train the critic only" in capsys.readouterr().out
    (run,) = glob.glob(str(tmp_path / "logs" / "rsl_rl" / "cartpole_direct" / "*"))
    first, second = (torch.load(os.path.join(run, f"model_{i}.pt"), weights_only=True) for i in (0, 1))
    assert _same(first["actor_state_dict"], given)  # the critic-only update left the actor as given
    assert not _same(second["actor_state_dict"], given)  # then the actor learns
    assert not _same(second["critic_state_dict"], first["critic_state_dict"])


def test_a_checkpoint_that_does_not_fit_is_refused_in_one_line(tmp_path, capsys):
    shipped = unpack_pretrained_checkpoint(MANAGER, "rsl_rl", str(tmp_path / "shipped"))
    fewer = "env.observations.policy.joint_vel_rel=null"  # 2 observations instead of 4
    assert _train(tmp_path, MANAGER, "--init_weights", shipped, fewer) == 2
    # the first layer of another size, with both sizes, in one line; no checkpoint written
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "does not fit simlab/Cartpole-v0" in err[0], err
    assert "[32, 4]" in err[0] and "[32, 2]" in err[0] and "Nothing was loaded" in err[0]
    assert not glob.glob(str(tmp_path / "logs" / "rsl_rl" / "cartpole" / "*" / "model_*.pt"))


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--init_weights", "{ckpt}", "--checkpoint", "{ckpt}"], "give one"),
        (["--init_weights", "{ckpt}", "--library", "skrl"], "supported with --library rsl_rl, not skrl"),
        (["--init_weights", "{ckpt}", "--warmup_critic", "-1"], "--warmup_critic must be >= 0"),
        (["--warmup_critic", "5"], "give that too"),
    ],
)
def test_init_weights_refuses_resume_other_libraries_and_a_lone_warmup(tmp_path, capsys, extra, message):
    shipped = unpack_pretrained_checkpoint(MANAGER, "rsl_rl", str(tmp_path / "shipped"))
    assert _train(tmp_path, MANAGER, *[e.format(ckpt=shipped) for e in extra]) == 2
    assert message in capsys.readouterr().err
