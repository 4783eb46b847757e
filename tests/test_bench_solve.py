"""`simlab bench solve`: trains with `simlab train`'s pieces, plays each checkpoint, stops at the first
that meets the criterion and prints where the time went (figures are not asserted, only their sums)."""

from __future__ import annotations

import glob
import json
import os

import pytest
import torch

from simlab.benchmarks.cli import main
from simlab.benchmarks.solve import time_to_policy
from simlab.cli.main import build_parser
from simlab.cli.train import run_train
from simlab.tasks.utils.criteria import criterion_for

TINY = ["--device", "cpu", "--num_envs", "32", "--eval_envs", "8", "--eval_seconds", "0.5", "--seed", "3"]


def _checkpoints(run_root) -> list[str]:
    return sorted(os.path.basename(p) for p in glob.glob(str(run_root / "rsl_rl" / "cartpole" / "*" / "model_*.pt")))


def test_every_checkpoint_is_played_and_training_is_what_simlab_train_does(tmp_path, capsys):
    out = tmp_path / "solve.json"
    argv = ["solve", *TINY, "--max_iterations", "3", "--eval_every", "1", "--log_root", str(tmp_path / "bench")]
    assert main([*argv, "--json", str(out)]) == 0
    printed = capsys.readouterr().out
    for column in ("time to policy s", "start-up s", "rollout s", "update s", "evaluation s", "wall s"):
        assert column in printed
    assert printed.count("[solve] model_") == 3  # iterations 0, 1, 2; the final save of model_2 is not played twice
    assert "not solved in 3 iterations; of " in printed and "start-up " in printed and "evaluation " in printed
    assert "[solve] start-up " in printed and "first env step " in printed and "first iteration " in printed

    (row,) = json.loads(out.read_text())["results"]["solve"]
    assert "error" not in row
    assert row["criterion"] == "|pole angle| < 0.2 rad in >= 95% of steps"
    assert [e["iteration"] for e in row["evaluations"]] == [0, 1, 2]
    assert not row["solved"] and row["time_to_policy_s"] is None  # 3 iterations do not balance a pole
    assert all(0.0 <= e["score"] < 0.95 and not e["passed"] for e in row["evaluations"])
    shares = [row[k] for k in ("startup_s", "rollout_s", "update_s", "evaluation_s")]
    assert all(s > 0 for s in shares) and row["other_s"] >= 0
    last = row["evaluations"][-1]
    assert sum(shares) + row["other_s"] == pytest.approx(last["saved_at_s"] + last["evaluation_s"])
    assert row["wall_s"] >= last["saved_at_s"] and row["num_envs"] == 32
    reached = row["startup_milestones_s"]
    assert list(reached)[0] == "command" and list(reached)[-1] == "first iteration"
    assert reached["first iteration"] <= row["evaluations"][0]["saved_at_s"]

    # playing the checkpoints left training alone: the same weights as `simlab train` with that seed
    plain = ["train", "--task", "simlab/Cartpole-v0", "--headless", "--device", "cpu", "--num_envs", "32"]
    plain += ["--max_iterations", "3", "--seed", "3", "--log_root", str(tmp_path / "plain")]
    run_train(build_parser().parse_args(plain), [])
    (benched,) = glob.glob(str(tmp_path / "bench" / "rsl_rl" / "cartpole" / "*" / "model_2.pt"))
    (trained,) = glob.glob(str(tmp_path / "plain" / "rsl_rl" / "cartpole" / "*" / "model_2.pt"))
    a, b = torch.load(benched), torch.load(trained)
    for model in ("actor_state_dict", "critic_state_dict"):
        assert all(torch.equal(a[model][k], b[model][k]) for k in a[model])


def test_training_stops_at_the_first_checkpoint_that_passes(tmp_path):
    row = time_to_policy(
        "simlab/Cartpole-v0",
        device="cpu",
        num_envs=32,
        max_iterations=20,
        eval_every=2,
        seed=3,
        eval_envs=8,
        eval_seconds=0.2,
        reward_threshold=-1e9,  # any policy keeps it: the first checkpoint solves the task
        log_root=str(tmp_path),
    )
    assert row["solved"] and row["iteration"] == 0 and len(row["evaluations"]) == 1
    assert row["criterion"] == "mean reward per env-step >= -1e+09"
    assert 0 < row["time_to_policy_s"] <= row["evaluations"][0]["saved_at_s"]
    assert _checkpoints(tmp_path) == ["model_0.pt"]  # no iteration ran after it


def test_bad_input_says_what_is_allowed(tmp_path):
    with pytest.raises(ValueError, match="trains with \\['rsl_rl'\\]; got --library sb3"):
        time_to_policy("simlab/Cartpole-v0", library="sb3", log_root=str(tmp_path))
    with pytest.raises(ValueError, match="Unknown task simlab/Nope-v0"):
        criterion_for("simlab/Nope-v0")


@pytest.mark.slow  # two fresh processes, the first compiling every module it imports
def test_fresh_processes_start_with_the_bytecode_the_first_one_cached(tmp_path, capsys):
    """``--processes 2 --pycache_prefix DIR``: two solves one after the other in fresh processes; the
    first compiles every module into the empty DIR, the second finds them all there."""
    out = tmp_path / "solve.json"
    argv = ["solve", *TINY, "--max_iterations", "1", "--log_root", str(tmp_path / "bench"), "--json", str(out)]
    argv += ["--processes", "2", "--pycache_prefix", str(tmp_path / "pyc")]
    assert main(argv) == 0
    first, second = json.loads(out.read_text())["results"]["solve"]
    assert (first["process"], second["process"]) == (1, 2)
    assert first["caches"]["pycache_prefix"] == str(tmp_path / "pyc") and not first["caches"]["dont_write_bytecode"]
    assert first["python_modules_compiled"] > 1000  # torch and the rest, compiled into the empty folder
    assert second["python_modules_compiled"] == 0
    assert first["warp_kernel_modules_compiled"] is None  # the CPU engine does not import Warp
    for row in (first, second):
        phases = row["startup_phases_s"]
        assert list(phases) == list(row["startup_milestones_s"])
        assert sum(phases.values()) == pytest.approx(row["startup_milestones_s"]["first iteration"])
    printed = capsys.readouterr().out
    assert "start-up phases (s spent reaching each milestone" in printed and "process 2: start-up " in printed


def test_cache_flags_need_fresh_processes(capsys):
    with pytest.raises(SystemExit):
        main(["solve", *TINY, "--pycache_prefix", "/tmp/x"])
    assert "give --processes N" in capsys.readouterr().err
