"""``simlab train --distributed`` on the CPU: two gloo processes under torchrun, and simlab's own launch."""

from __future__ import annotations

import argparse
import glob
import os
import signal
import subprocess
import sys
import time

import pytest
import torch
from conftest import wait_for

from simlab.cli import distributed
from simlab.cli.main import main

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WORKER = os.path.join(REPO, "tests", "distributed_worker.py")
SMALL = ["--task", "simlab/Cartpole-v0", "--num_envs", "8", "--headless", "--device", "cpu"]
MARL_TASK = "simlab/Cart-Double-Pendulum-Direct-v0"


def _env(**extra: str) -> dict[str, str]:
    env = dict(os.environ, OMP_NUM_THREADS="1", NCCL_NVLS_ENABLE="0", PYTHONPATH=REPO, **extra)
    for name in ("RANK", "LOCAL_RANK", "WORLD_SIZE"):
        env.pop(name, None)
    return env


def _torchrun(
    tmp_path, *argv: str, timeout: float = 300, device: str = "cpu", **extra: str
) -> subprocess.CompletedProcess:
    cmd = [sys.executable, "-m", "torch.distributed.run", "--standalone", "--nproc_per_node=2", WORKER]
    cmd += [str(tmp_path), "train", *SMALL, "--device", device, "--log_root", str(tmp_path / "logs")]
    cmd += ["--distributed", *argv]
    return subprocess.run(cmd, env=_env(**extra), capture_output=True, text=True, timeout=timeout, cwd=tmp_path)


def _runs(tmp_path, library: str) -> list[str]:
    return sorted(glob.glob(str(tmp_path / "logs" / library / "*" / "*")))


def _assert_in_sync(tmp_path) -> None:
    rank0, rank1 = (torch.load(tmp_path / f"rank{r}.pt") for r in (0, 1))
    assert rank0["weights"].keys() == rank1["weights"].keys()
    for name, w0 in rank0["weights"].items():
        assert torch.equal(w0, rank1["weights"][name]), f"{name} differs between the ranks"
    # other seeds: the ranks simulated other episodes
    assert not torch.allclose(rank0["first_obs"], rank1["first_obs"])


@pytest.mark.parametrize(
    ("library", "args", "checkpoint_glob"),
    [
        ("rsl_rl", ["--max_iterations", "3", "agent.save_interval=1"], "model_1.pt"),
        ("skrl", ["--max_iterations", "3", "agent.agent.rollouts=8"], "checkpoints/agent_*.pt"),
        (
            "skrl",
            ["--task", MARL_TASK, "--algorithm", "MAPPO", "--max_iterations", "2", "agent.agent.rollouts=8"],
            "checkpoints/agent_*.pt",
        ),
    ],
    ids=["rsl_rl", "skrl", "skrl-mappo"],
)
@pytest.mark.slow  # two torchrun launches of two training processes each, per library
def test_two_gloo_ranks_train_in_sync_and_resume(tmp_path, library, args, checkpoint_glob):
    done = _torchrun(tmp_path, "--library", library, *args)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    _assert_in_sync(tmp_path)
    runs = _runs(tmp_path, library)
    assert len(runs) == 1, runs  # only rank 0 wrote a run folder
    assert sorted(os.listdir(tmp_path)) == ["logs", "rank0.pt", "rank1.pt"]  # and nothing else
    assert glob.glob(os.path.join(runs[0], "**", "events.out.tfevents.*"), recursive=True)
    checkpoint = sorted(glob.glob(os.path.join(runs[0], checkpoint_glob)))[0]

    # the resumed run gets a new run folder, even within the same second (`<time>_1`), sorted after the first
    resumed = _torchrun(tmp_path, "--library", library, *args, "--checkpoint", checkpoint)
    assert resumed.returncode == 0, resumed.stdout[-3000:] + resumed.stderr[-3000:]
    assert "Resumed" in resumed.stdout
    _assert_in_sync(tmp_path)
    assert len(_runs(tmp_path, library)) == 2
    if library == "rsl_rl":  # the iterations go on from the checkpoint's
        assert torch.load(os.path.join(_runs(tmp_path, library)[1], "model_3.pt"), weights_only=False)["iter"] == 3


@pytest.mark.gpu
@pytest.mark.skipif(torch.cuda.device_count() < 2, reason="needs two GPUs")
@pytest.mark.parametrize("library", ["rsl_rl", "skrl", "rl_games"])
def test_two_gpus_train_in_sync(tmp_path, library):
    """NCCL: one process per GPU, each simulating on cuda:<local_rank>."""
    done = _torchrun(tmp_path, "--library", library, "--num_envs", "64", "--max_iterations", "3", device="cuda")
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert "on cuda:0, 64 envs on each of 2 processes" in done.stdout
    _assert_in_sync(tmp_path)
    assert len(_runs(tmp_path, library)) == 1


def test_mismatched_ranks_are_reported(tmp_path):
    done = _torchrun(tmp_path, "--library", "rsl_rl", "--max_iterations", "1", SIMLAB_TEST_RANK1_NUM_ENVS="4")
    assert done.returncode != 0
    assert "num_envs: rank 0 has 8, rank 1 has 4" in done.stderr


def test_a_crashed_rank_stops_the_run(tmp_path):
    start = time.perf_counter()
    done = _torchrun(tmp_path, "--library", "rsl_rl", "--max_iterations", "50", timeout=120, SIMLAB_TEST_CRASH_RANK="1")
    assert done.returncode != 0
    assert time.perf_counter() - start < 120
    assert "RuntimeError: test crash on rank 1" in done.stderr  # its traceback, printed by simlab's CLI
    # torchrun names a root cause: rank 1, or rank 0 when its collective fails first ("connection closed")
    assert "Root Cause (first observed failure):" in done.stderr


def test_simlab_launches_torchrun_itself(tmp_path):
    cmd = [sys.executable, "-m", "simlab", "train", *SMALL, "--library", "rsl_rl", "--max_iterations", "2"]
    cmd += ["--log_root", str(tmp_path / "logs"), "--distributed", "--nproc_per_node", "2"]
    done = subprocess.run(cmd, env=_env(), capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert "torch.distributed.run --nproc_per_node=2" in done.stdout
    assert "8 envs on each of 2 processes" in done.stdout
    assert len(_runs(tmp_path, "rsl_rl")) == 1


def test_isaaclab_train_script_under_torchrun(tmp_path):
    script = os.path.join(REPO, "scripts", "reinforcement_learning", "rsl_rl", "train.py")
    cmd = [sys.executable, "-m", "torch.distributed.run", "--standalone", "--nproc_per_node=2", script]
    cmd += ["--task", "Isaac-Cartpole-v0", "--num_envs", "8", "--headless", "--device", "cpu"]
    cmd += ["--max_iterations", "2", "--distributed"]
    done = subprocess.run(cmd, env=_env(), capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert "8 envs on each of 2 processes" in done.stdout
    assert len(_runs(tmp_path, "rsl_rl")) == 1


def _launch_args(**values: str | None) -> argparse.Namespace:
    args = argparse.Namespace(**{name: None for name in distributed.LAUNCH_FLAGS})
    vars(args).update(values)
    return args


def test_launch_command_passes_torchrun_flags_through():
    argv = ["train", "--task", "T", "--distributed", "--nproc_per_node", "4", "--nnodes=2"]
    argv += ["--rdzv_endpoint", "h:29400"]
    args = _launch_args(nproc_per_node="4", nnodes="2", rdzv_endpoint="h:29400")
    cmd = distributed.launch_command(args, argv, "cuda:0")
    assert cmd[1:5] == ["-m", "torch.distributed.run", "--nproc_per_node=4", "--nnodes=2"]
    assert "--rdzv_endpoint=h:29400" in cmd and "--standalone" not in cmd
    assert cmd[cmd.index("simlab") + 1 :] == ["train", "--task", "T", "--distributed"]
    assert "--standalone" in distributed.launch_command(_launch_args(nproc_per_node="2"), argv, "cpu")


def test_distributed_errors_say_what_is_supported(tmp_path, capsys):
    log = ["--log_root", str(tmp_path / "logs")]
    assert main(["train", *SMALL, "--library", "sb3", "--distributed", "--nproc_per_node", "2", *log]) == 2
    assert "supports ['rsl_rl', 'skrl', 'rl_games']" in capsys.readouterr().err
    assert main(["train", *SMALL, "--distributed", *log]) == 2
    assert "--nproc_per_node" in capsys.readouterr().err
    assert main(["train", *SMALL, "--distributed", "--nproc_per_node", "1", *log]) == 2
    assert "at least 2 processes" in capsys.readouterr().err
    assert main(["train", *SMALL, "--library", "rl_games", "--distributed", "--nproc_per_node", "2", *log]) == 2
    assert "rl_games' multi_gpu mode runs on CUDA GPUs only" in capsys.readouterr().err
    assert not os.path.exists(tmp_path / "logs")


def test_ctrl_c_on_the_launcher_saves_rank_0s_checkpoint(tmp_path):
    cmd = [sys.executable, "-m", "simlab", "train", *SMALL, "--library", "rsl_rl", "--max_iterations", "100000"]
    cmd += ["--log_root", str(tmp_path / "logs"), "--distributed", "--nproc_per_node", "2", "agent.save_interval=1"]
    with open(tmp_path / "out.txt", "w") as out:
        launcher = subprocess.Popen(
            cmd, env=_env(PYTHONUNBUFFERED="1"), stdout=out, stderr=out, cwd=tmp_path, start_new_session=True
        )

        def past_the_first_iteration():  # rank 0 checkpoints every iteration: model_1.pt is iteration 1 done
            assert launcher.poll() is None, (tmp_path / "out.txt").read_text()[-3000:]
            return glob.glob(str(tmp_path / "logs" / "rsl_rl" / "*" / "*" / "model_1.pt"))

        wait_for(past_the_first_iteration, 120, "rank 0's second checkpoint")
        os.killpg(launcher.pid, signal.SIGINT)  # the terminal's Ctrl+C: the whole foreground group
        assert launcher.wait(timeout=120) == 130
    text = (tmp_path / "out.txt").read_text()
    assert "Interrupted: saved" in text, text[-3000:]
    (run,) = _runs(tmp_path, "rsl_rl")
    saved = text.split("Interrupted: saved ")[1].split()[0]
    assert os.path.dirname(saved) == run and torch.load(saved, weights_only=False)["iter"] > 0
