"""`simlab train`'s start-up milestones, and the rsl_rl rollout without a host read per env step:
the episode logs picked once per iteration are the ones Isaac Lab's per-step choice gives, and
training writes the same weights."""

from __future__ import annotations

import gc
import glob
import os
import re
import subprocess
import sys

import pytest
import torch
from conftest import run_logs
from torch.utils.tensorboard import SummaryWriter

import simlab.cli.libraries.rsl_rl as rsl_rl_adapter
from simlab.cli.main import build_parser
from simlab.cli.train import run_train
from simlab.utils.startup import MILESTONES_PREFIX, bytecode_hint, milestones

TRAIN = ["train", "--task", "simlab/Cartpole-v0", "--headless", "--device", "cpu", "--num_envs", "16", "--seed", "5"]


def test_train_marks_its_start_up_in_order(tmp_path, capsys):
    run_train(
        build_parser().parse_args([*TRAIN, "--max_iterations", "1", "--verbose", "--log_root", str(tmp_path)]), []
    )
    (line,) = [line for line in capsys.readouterr().out.splitlines() if line.startswith(MILESTONES_PREFIX)]
    printed = dict(re.findall(r"([a-z -]+)=([0-9.]+)", line[len(MILESTONES_PREFIX) :]))
    names = [name.strip() for name in printed]
    assert names == list(milestones())
    expected = ["command", "configs", "library", "model compiled", "physics backend", "physics reset", "env"]
    expected += ["runner", "first env step", "first iteration"]
    assert names == expected
    seconds = [float(v) for v in printed.values()]
    assert seconds == sorted(seconds) and seconds[0] > 0


def _train_and_record(tmp_path, name: str, monkeypatch: pytest.MonkeyPatch) -> tuple[list, dict]:
    """Train 4 iterations; the scalars rsl_rl logs and the final weights."""
    scalars: list[tuple[str, float, int]] = []

    def add_scalar(self, tag, value, step=None, *args, **kwargs):
        scalars.append((tag, float(value), step))

    monkeypatch.setattr(SummaryWriter, "add_scalar", add_scalar)
    root = tmp_path / name
    # 1 s (60-step) episodes over 16 envs: about one step in four has a reset
    argv = [*TRAIN, "--max_iterations", "4", "--log_root", str(root)]
    run_train(build_parser().parse_args(argv), ["env.episode_length_s=1.0"])
    (final,) = glob.glob(str(root / "rsl_rl" / "cartpole" / "*" / "model_3.pt"))
    return scalars, torch.load(final)


def test_episode_logs_picked_per_iteration_match_the_per_step_choice(tmp_path, monkeypatch):
    enabled = []
    original = rsl_rl_adapter._logs_without_host_sync

    def spy(runner, logger):
        original(runner, logger)
        enabled.append(runner.env.unwrapped.log_refresh_on_device)

    monkeypatch.setattr(rsl_rl_adapter, "_logs_without_host_sync", spy)
    deferred, deferred_weights = _train_and_record(tmp_path, "deferred", monkeypatch)
    assert enabled == [True]
    monkeypatch.setattr(rsl_rl_adapter, "_logs_without_host_sync", lambda runner, logger: None)
    per_step, per_step_weights = _train_and_record(tmp_path, "per_step", monkeypatch)

    def episode_logs(scalars):
        return run_logs(scalars, ("Episode_", "Physics/", "Train/mean_"))

    assert {tag for tag, _, _ in episode_logs(deferred)} >= {
        "Episode_Reward/alive",
        "Episode_Termination/time_out",
        "Train/mean_reward",
    }
    assert episode_logs(deferred) == episode_logs(per_step)
    for model in ("actor_state_dict", "critic_state_dict", "optimizer_state_dict"):
        a, b = deferred_weights[model], per_step_weights[model]
        if model == "optimizer_state_dict":
            a, b = a["state"], b["state"]
            assert all(torch.equal(a[i][k], b[i][k]) for i in a for k in a[i])
        else:
            assert all(torch.equal(a[k], b[k]) for k in a)


def test_a_library_compiled_from_source_is_named_with_the_fix(tmp_path):
    code = (
        "import json\n"
        "from simlab.utils.startup import bytecode_hint, compiled_from_source\n"
        "print(compiled_from_source(('json', 'not_imported')))\n"
        "print(bytecode_hint(('json',)))\n"
    )
    # an empty bytecode cache that Python may not write to: every module is compiled from source
    uncached = {**os.environ, "PYTHONPYCACHEPREFIX": str(tmp_path), "PYTHONDONTWRITEBYTECODE": "1"}
    out = subprocess.run([sys.executable, "-c", code], env=uncached, capture_output=True, text=True, check=True)
    listed, hint = out.stdout.splitlines()[-2:]
    assert listed == "['json']"
    assert "compiled json from source" in hint and "PYTHONDONTWRITEBYTECODE is set" in hint
    assert "PYTHONPYCACHEPREFIX" in hint
    assert bytecode_hint(("json",)) is None  # this process found json's bytecode cached


# run in a `simlab train` process: whether the collector runs while the configs load (start-up) and
# when the runner is built (training), and whether the start-up's objects were frozen by then
_COLLECTOR_PROBE = """
import gc, sys
import simlab.cli.libraries.rsl_rl as library
import simlab.cli.train as train
from simlab.cli.main import main

def spy(name, function):
    def wrapped(*args, **kwargs):
        print(name, "collector on", gc.isenabled(), "frozen", gc.get_freeze_count() > 0)
        return function(*args, **kwargs)
    return wrapped

train.load_configs = spy("configs:", train.load_configs)
library.make_runner = spy("runner:", library.make_runner)
sys.argv = ["simlab", *sys.argv[1:]]
code = main()
print("at exit: frozen", gc.get_freeze_count() > 0)
sys.exit(code)
"""


def test_the_command_skips_the_exit_collection_and_loses_no_log(tmp_path):
    """The ``simlab`` command pauses Python's garbage collector for its start-up and resumes it, the
    start-up's objects frozen, before training; it freezes its objects out of the collection at exit;
    everything the run wrote (checkpoints, every iteration's TensorBoard scalars) is on disk. Called
    from Python (a test, a script), ``main`` leaves the garbage collector alone."""
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    from simlab.cli.main import main

    argv = [*TRAIN, "--max_iterations", "3", "--log_root", str(tmp_path / "cli")]
    out = subprocess.run([sys.executable, "-c", _COLLECTOR_PROBE, *argv], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr[-2000:]
    assert "configs: collector on False frozen False" in out.stdout
    assert "runner: collector on True frozen True" in out.stdout
    assert "at exit: frozen True" in out.stdout
    (run,) = glob.glob(str(tmp_path / "cli" / "rsl_rl" / "cartpole" / "*"))
    saved = sorted(os.path.basename(p) for p in glob.glob(os.path.join(run, "model_*.pt")))
    assert saved == ["model_0.pt", "model_2.pt"]
    (events,) = glob.glob(os.path.join(run, "events.out.tfevents*"))
    scalars = EventAccumulator(events)
    scalars.Reload()
    assert [e.step for e in scalars.Scalars("Loss/value")] == [0, 1, 2]

    frozen_before = gc.get_freeze_count()
    assert main([*TRAIN, "--max_iterations", "1", "--log_root", str(tmp_path / "in_process")]) == 0
    assert gc.get_freeze_count() == frozen_before and gc.isenabled()


def test_start_up_is_timed_from_python_when_a_shell_execs_it():
    # `bash -c "bash scripts/setup.sh && simlab train ..."` runs simlab in the shell's own process
    # (exec): /proc then dates it from the shell's start, and the setup's 20 s read as start-up
    code = "import simlab.utils.startup as s; print(s.seconds_since_process_start())"
    shell = f"sleep 3; exec {sys.executable} -c '{code}'"
    out = subprocess.run(["bash", "-c", shell], capture_output=True, text=True, check=True, timeout=60)
    assert float(out.stdout) < 2.5
