"""Nothing lost, nothing silent: run folders, checkpoints, signals, resume, divergence and bad flags (issue 16)."""

from __future__ import annotations

import glob
import os
import signal
import subprocess
import sys
import time
import warnings

import pytest
import torch
from conftest import rendering_available, wait_for

from simlab.cli.checkpoints import find_last_checkpoint
from simlab.cli.main import main
from simlab.cli.runs import make_run_dir
from simlab.utils.errors import CheckpointError, ConfigError, SimlabError, is_intended_error
from simlab.utils.io import atomic_path, atomic_torch_saves, dump_yaml, load_yaml

TASK = "simlab/Cartpole-v0"
SMALL = ["--task", TASK, "--num_envs", "8", "--headless", "--device", "cpu"]
REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _run(tmp_path, *argv) -> int:
    return main([*argv, "--log_root", str(tmp_path / "logs")])


def _runs(tmp_path, library="rsl_rl") -> list[str]:
    return sorted(glob.glob(str(tmp_path / "logs" / library / "*" / "*")))


def _train(tmp_path, *extra, library="rsl_rl") -> str:
    """A tiny training; returns its run folder."""
    before = set(_runs(tmp_path, library))
    assert _run(tmp_path, "train", *SMALL, "--library", library, "--max_iterations", "2", *extra) == 0
    (run,) = set(_runs(tmp_path, library)) - before
    return run


def _subprocess_env() -> dict[str, str]:
    return {**os.environ, "PYTHONPATH": REPO + os.pathsep + os.environ.get("PYTHONPATH", "")}


# --- item 1: run folders -------------------------------------------------------------------------


def test_two_processes_started_together_get_their_own_run_folder(tmp_path):
    # Both processes import first and say so; only then is the shared instant (early in a second) fixed and sent to
    # them, so a slow start on a loaded machine cannot put them in different seconds.
    code = (
        "import sys, time; from simlab.cli.runs import make_run_dir; "
        "print('ready', flush=True); start = float(sys.stdin.readline()); "
        "time.sleep(max(0.0, start - time.time())); "
        f"print(make_run_dir({str(tmp_path)!r}, 'rsl_rl', 'cartpole'))"
    )
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", code],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            env=_subprocess_env(),
            text=True,
        )
        for _ in range(2)
    ]
    assert [p.stdout.readline().strip() for p in procs] == ["ready", "ready"]
    start = int(time.time()) + 1.2
    for p in procs:  # both get the instant before either is waited for
        p.stdin.write(f"{start}\n")
        p.stdin.flush()
    folders = [p.communicate(timeout=60)[0].strip() for p in procs]
    assert all(p.returncode == 0 for p in procs)
    assert folders[0] != folders[1] and all(os.path.isdir(f) for f in folders), folders
    assert os.path.basename(folders[0])[:19] == os.path.basename(folders[1])[:19]  # the same second


def test_run_folder_names_in_one_second_are_unique_and_ordered(tmp_path):
    folders = [make_run_dir(str(tmp_path), "rsl_rl", "cartpole", "x") for _ in range(3)]
    assert len(set(folders)) == 3
    # a later run sorts after an earlier one, so --use_last_checkpoint finds the newest
    names = [os.path.basename(f) for f in folders]
    if names[0][:19] == names[2][:19]:
        assert names[1] == names[0] + "_1" and names[2] == names[0] + "_2"


# --- item 3: checkpoints of another library or task ----------------------------------------------


def test_play_refuses_a_checkpoint_of_another_library_or_task(tmp_path, capsys):
    run = _train(tmp_path)
    ckpt = os.path.join(run, "model_1.pt")
    exported = os.path.join(run, "exported")
    info = load_yaml(os.path.join(run, "params", "run.yaml"))
    assert info["task"] == TASK and info["library"] == "rsl_rl"
    assert info["observations"] == {"policy": 4} and info["actions"] == 1
    capsys.readouterr()

    assert _run(tmp_path, "play", *SMALL, "--library", "skrl", "--checkpoint", ckpt, "--steps", "2") == 2
    err = capsys.readouterr().err
    assert "written by rsl_rl, not skrl" in err and "--force" in err
    assert not os.path.exists(exported)  # nothing overwritten

    other = ["--task", "simlab/Cartpole-Direct-v0", "--num_envs", "8", "--device", "cpu"]
    assert _run(tmp_path, "play", *other, "--checkpoint", ckpt, "--steps", "2") == 2
    err = capsys.readouterr().err
    assert "trained the task 'simlab/Cartpole-v0', not 'simlab/Cartpole-Direct-v0'" in err
    assert not os.path.exists(exported)

    # the same task with another observation size (an override removed a term)
    assert _run(tmp_path, "play", *SMALL, "--checkpoint", ckpt, "env.observations.policy.joint_vel_rel=null") == 2
    assert "observations sizes are {'policy': 4}; this env's are {'policy': 2}" in capsys.readouterr().err
    assert not os.path.exists(exported)

    # a run trained with an override that changes the sizes: the refusal names it, to be given again
    drop = "env.observations.policy.joint_vel_rel=null"
    trained_without_it = os.path.join(_train(tmp_path, drop), "model_1.pt")
    assert load_yaml(os.path.join(os.path.dirname(trained_without_it), "params", "run.yaml"))["env_overrides"] == [drop]
    assert _run(tmp_path, "play", *SMALL, "--checkpoint", trained_without_it, "--steps", "2") == 2
    assert f"its run was trained with {drop}: give this command the same" in capsys.readouterr().err
    assert _run(tmp_path, "play", *SMALL, "--checkpoint", trained_without_it, "--steps", "2", drop) == 0
    capsys.readouterr()

    # resuming training from another task's checkpoint is refused the same way, before a run folder exists
    assert _run(tmp_path, "train", *other, "--max_iterations", "1", "--checkpoint", ckpt) == 2
    assert "not 'simlab/Cartpole-Direct-v0'" in capsys.readouterr().err
    assert not glob.glob(str(tmp_path / "logs" / "rsl_rl" / "cartpole_direct*"))

    # --force plays it anyway (same sizes), with a warning
    assert _run(tmp_path, "play", *other, "--checkpoint", ckpt, "--steps", "2", "--force") == 0
    assert "WARNING (--force)" in capsys.readouterr().err
    assert os.path.isfile(os.path.join(exported, "policy.onnx"))


def test_play_seconds_runs_that_much_simulated_time(tmp_path):
    from simlab.cli.main import build_parser
    from simlab.cli.play import run_play

    _train(tmp_path)
    argv = ["play", *SMALL, "--use_last_checkpoint", "--seconds", "0.5", "--log_root", str(tmp_path / "logs")]
    result = run_play(build_parser().parse_args(argv), [])
    assert result["steps"] == 30  # the cartpole's env step is 1/120 s * decimation 2


# --- items 4 & 10: bad flags and overrides -------------------------------------------------------


@pytest.mark.parametrize(
    ("flags", "message"),
    [
        (["train", "--max_iterations", "0"], "--max_iterations must be at least 1, got 0"),
        (["train", "--max_iterations", "-3"], "--max_iterations must be at least 1, got -3"),
        (["train", "agent.max_iterations=0"], "agent.max_iterations must be a whole number >= 1 to train, got 0"),
        (["train", "--library", "skrl", "agent.trainer.timesteps=0"], "agent.trainer.timesteps must be a whole number"),
        (
            ["train", "agent.num_steps_per_env=-5"],
            "agent.num_steps_per_env must be a whole number >= 1 to train, got -5",
        ),
        (["train", "agent.algorithm.num_mini_batches=0"], "agent.algorithm.num_mini_batches must be a whole number"),
        (["train", "--library", "skrl", "agent.agent.rollouts=2.5"], "agent.agent.rollouts must be a whole number"),
        (["train", "--library", "sb3", "agent.n_epochs=0"], "agent.n_epochs must be a whole number >= 1 to train"),
        (["train", "--library", "rl_games", "agent.params.config.horizon_length=-1"], "horizon_length must be a"),
        (
            ["train", "--library", "rl_games", "agent.params.config.minibatch_size=20"],
            "minibatch_size=20 does not divide the batch of 16 steps x 8 envs = 128, which rl_games requires;"
            " sizes that do: 16 or 32",
        ),
        (["train", "agent.algorithm.learning_rate=-1"], "agent.algorithm.learning_rate must be a finite number >= 0"),
        (["train", "--library", "skrl", "agent.agent.learning_rate=nan"], "agent.agent.learning_rate must be a finite"),
        (["train", "--video", "--video_length", "0"], "--video_length must be at least 1, got 0"),
        (["train", "--video", "--video_length", "-5"], "--video_length must be at least 1, got -5"),
        (["train", "--video", "--video_length", "50", "--video_interval", "20"], "longer than --video_interval 20"),
        (["play", "--use_last_checkpoint", "--video", "--video_length", "0"], "--video_length must be at least 1"),
        (["play", "--use_last_checkpoint", "--steps", "0"], "--steps must be at least 1, got 0"),
        (["play", "--use_last_checkpoint", "--seconds", "0"], "--seconds must be > 0 (simulated seconds), got 0.0"),
        (["play", "--use_last_checkpoint", "--seconds", "2", "--steps", "9"], "--seconds and --steps both set how"),
        (["random", "--steps", "-1"], "--steps must be at least 1, got -1"),
        (["train", "env.scene.num_envs=64.5"], "'env.scene.num_envs=64.5': this field is an integer (int), got 64.5"),
    ],
)
def test_bad_flags_are_refused_before_anything_is_written(tmp_path, capsys, flags, message):
    command, rest = flags[0], flags[1:]
    assert _run(tmp_path, command, *SMALL, *rest) == 2
    err = capsys.readouterr().err
    assert message in err, err
    assert len(err.strip().splitlines()) == 1  # one line, no config dump, no traceback
    assert not os.path.exists(tmp_path / "logs")


def test_rl_games_minibatch_above_the_batch_trains_one_minibatch_and_says_so(capsys):
    """A config tuned for 4096 envs (minibatch_size 8192) with --num_envs 8: rl_games would refuse it;
    the whole rollout becomes one mini-batch, in one printed line."""
    from simlab.cli.libraries.rl_games import _fitting_minibatch

    assert _fitting_minibatch(8192, 16, 8) == 128
    (line,) = capsys.readouterr().out.splitlines()
    assert "minibatch_size=8192" in line and "16 steps x 8 envs" in line and "one mini-batch of 128" in line
    assert _fitting_minibatch(64, 16, 8) == 64 and not capsys.readouterr().out  # a divisor stays, silently


def test_rl_games_central_value_minibatch_fits_the_rollout_too(capsys):
    """The OpenAI Shadow LSTM config's critic has its own minibatch_size (32768): with a few envs rl_games
    divided by zero mini-batches (a ZeroDivisionError traceback); it becomes the rollout, said in one line."""
    import argparse

    from simlab.cli.libraries import rl_games
    from simlab.tasks.utils import load_cfg_from_registry
    from simlab.tasks.utils.parse_cfg import parse_env_cfg

    task = "simlab/Repose-Cube-Shadow-OpenAI-LSTM-Direct-v0"
    agent_cfg = load_cfg_from_registry(task, "rl_games_cfg_entry_point")
    env_cfg = parse_env_cfg(task, device="cpu", num_envs=4)
    rl_games.configure(agent_cfg, argparse.Namespace(seed=None, max_iterations=2), env_cfg)
    config = agent_cfg["params"]["config"]
    assert config["minibatch_size"] == config["central_value_config"]["minibatch_size"] == 4 * config["horizon_length"]
    assert "central_value_config.minibatch_size=32768 is more than a rollout" in capsys.readouterr().out


def test_exponent_numbers_in_overrides(tmp_path):
    from simlab.tasks.utils.hydra import parse_override

    assert parse_override("agent.x=1e9")[1] == 1e9
    assert parse_override("agent.x=-2.5E-3")[1] == -2.5e-3
    assert parse_override("agent.x=1e")[1] == "1e"  # not a number: stays text
    run = _train(tmp_path, "agent.algorithm.learning_rate=1e-4", "agent.save_interval=1e0")
    agent = load_yaml(os.path.join(run, "params", "agent.yaml"))
    assert agent["algorithm"]["learning_rate"] == 1e-4 and agent["save_interval"] == 1


# --- item 6: atomic writes, torn checkpoints -----------------------------------------------------


class _FailsHalfway:
    """Pickles to a few bytes, then fails: a write cut off in the middle."""

    def __reduce__(self):
        raise OSError("disk full")


def test_a_write_that_fails_keeps_the_previous_file(tmp_path):
    path = tmp_path / "model.pt"
    torch.save({"w": torch.ones(3)}, path)
    with atomic_torch_saves(), pytest.raises(OSError, match="disk full"):
        torch.save({"w": torch.zeros(3), "x": _FailsHalfway()}, str(path))
    assert torch.equal(torch.load(path)["w"], torch.ones(3))
    assert os.listdir(tmp_path) == ["model.pt"]  # no temporary file left behind

    dump_yaml(tmp_path / "env.yaml", {"a": 1})
    with pytest.raises(Exception):  # noqa: B017 - yaml cannot represent the object: the write stops midway
        dump_yaml(tmp_path / "env.yaml", {"b": 2, "z": object()})
    assert load_yaml(tmp_path / "env.yaml") == {"a": 1}

    with pytest.raises(RuntimeError), atomic_path(tmp_path / "policy.onnx") as tmp:
        with open(tmp, "w") as f:
            f.write("half")
        raise RuntimeError("exporter crashed")
    assert not os.path.exists(tmp_path / "policy.onnx")


def test_an_unreadable_checkpoint_whose_error_has_no_message_is_still_one_line(tmp_path, monkeypatch):
    """Corrupt bytes can make pickle raise an error without a message (a MemoryError, seen in CI)."""
    from simlab.cli.checkpoints import read_checkpoint
    from simlab.utils.errors import CheckpointError

    path = tmp_path / "model_3.pt"
    path.write_bytes(b"not a checkpoint")

    def load(*args, **kwargs):
        raise MemoryError

    monkeypatch.setattr(torch, "load", load)
    with pytest.raises(CheckpointError, match=r"cannot be read \(MemoryError\): it is truncated, corrupt"):
        read_checkpoint(str(path))


def test_an_exported_policy_given_as_checkpoint_is_named_as_such(tmp_path):
    """play --checkpoint exported/policy.pt or .onnx: torch called it corrupt and advised weights_only=False."""
    from simlab.cli.checkpoints import read_checkpoint

    scripted = tmp_path / "policy.pt"
    torch.jit.save(torch.jit.script(torch.nn.Linear(2, 1)), str(scripted))
    (tmp_path / "policy.onnx").write_bytes(b"\x08\x07\x12\x07pytorch")
    for path, kind in ((scripted, "TorchScript"), (tmp_path / "policy.onnx", "ONNX")):
        with pytest.raises(CheckpointError, match=rf"is an exported {kind} policy .* not a training checkpoint") as e:
            read_checkpoint(str(path))
        assert "weights_only" not in str(e.value)
    weights = tmp_path / "model_3.pt"
    torch.save({"iter": 3, "model_state_dict": torch.nn.Linear(2, 1).state_dict()}, weights)
    assert read_checkpoint(str(weights))["iter"] == 3  # a zip of weights is a checkpoint still


def test_an_experiment_folder_given_as_checkpoint_names_its_newest_run(tmp_path):
    """--checkpoint logs/rsl_rl/<experiment> (the folder of runs): 'No checkpoint in the run folder' before."""
    from simlab.cli.checkpoints import resolve_checkpoint
    from simlab.utils.errors import CheckpointNotFoundError

    for run in ("2026-01-01_10-00-00", "2026-01-02_10-00-00", "2026-01-03_10-00-00"):
        (tmp_path / "exp" / run).mkdir(parents=True)
    for run in ("2026-01-01_10-00-00", "2026-01-02_10-00-00"):  # the newest run has none yet
        torch.save({"iter": 1, "model_state_dict": {}}, tmp_path / "exp" / run / "model_1.pt")
    newest = tmp_path / "exp" / "2026-01-02_10-00-00"
    with pytest.raises(CheckpointNotFoundError, match=rf"holds run folders, not checkpoints.*'{newest}'"):
        resolve_checkpoint(str(tmp_path / "exp"), "rsl_rl")
    (tmp_path / "empty").mkdir()
    with pytest.raises(CheckpointNotFoundError, match=r"No checkpoint in the run folder"):
        resolve_checkpoint(str(tmp_path / "empty"), "rsl_rl")
    assert resolve_checkpoint(str(newest), "rsl_rl") == str(newest / "model_1.pt")


def test_play_names_the_env_overrides_its_run_trained_with_and_it_lacks(tmp_path, capsys):
    """A tracking policy trained on another clip fits the default clip in size: play used it silently."""
    from simlab.cli.checkpoints import note_missing_env_overrides

    run = tmp_path / "run"
    (run / "params").mkdir(parents=True)
    trained = ["env.commands.motion.motion_file=dance.npz", "env.rewards.x.weight=2"]
    dump_yaml(str(run / "params" / "run.yaml"), {"task": "simlab/Tracking-Flat-G1-v0", "env_overrides": trained})
    checkpoint = str(run / "model_1.pt")
    assert note_missing_env_overrides(checkpoint, ["env.rewards.x.weight=3"]) == [trained[0]]
    assert "trained with env.commands.motion.motion_file=dance.npz, which this command does not give" in (
        capsys.readouterr().out
    )
    assert note_missing_env_overrides(checkpoint, [f"+{trained[0]}", "env.rewards.x.weight=2"]) == []
    assert not capsys.readouterr().out
    # how many envs the run stepped and its seed are no part of what the policy learned: not named
    run_settings = ["env.scene.num_envs=512", "env.seed=7"]
    dump_yaml(str(run / "params" / "run.yaml"), {"task": "simlab/Tracking-Flat-G1-v0", "env_overrides": run_settings})
    assert note_missing_env_overrides(checkpoint, []) == []
    assert not capsys.readouterr().out


def test_torn_newest_checkpoint_is_skipped_with_a_warning(tmp_path, capsys):
    run = _train(tmp_path, "agent.save_interval=1")
    newest, previous = os.path.join(run, "model_1.pt"), os.path.join(run, "model_0.pt")
    with open(newest, "rb") as f:
        data = f.read()
    with open(newest, "wb") as f:  # what a crash in the middle of the old in-place torch.save left
        f.write(data[: len(data) // 2])
    capsys.readouterr()

    assert find_last_checkpoint(str(tmp_path / "logs"), "rsl_rl", "cartpole") == previous
    err = capsys.readouterr().err
    assert "model_1.pt" in err and f"using '{previous}' instead" in err

    assert _run(tmp_path, "play", *SMALL, "--checkpoint", run, "--steps", "2", "--no_export") == 0
    assert f"using '{previous}' instead" in capsys.readouterr().err

    # the torn file named explicitly: a one-line simlab error, no traceback
    assert _run(tmp_path, "play", *SMALL, "--checkpoint", newest, "--steps", "2") == 2
    err = capsys.readouterr().err
    assert "cannot be read" in err and "truncated" in err and "Traceback" not in err

    with open(previous, "wb") as f:
        f.write(bytes(range(256)) * 8)  # corrupt (fixed bytes: random ones made pickle raise anything)
    with open(newest, "wb"):
        pass  # empty
    assert _run(tmp_path, "play", *SMALL, "--use_last_checkpoint", "--steps", "2") == 2
    err = capsys.readouterr().err
    assert "No readable checkpoint" in err and "empty (0 bytes)" in err and "Traceback" not in err


# --- item 7: SIGTERM -----------------------------------------------------------------------------


def test_sigterm_saves_a_checkpoint(tmp_path):
    logs = tmp_path / "logs"
    cmd = [sys.executable, "-m", "simlab", "train", *SMALL, "--max_iterations", "100000", "--log_root", str(logs)]
    with open(tmp_path / "out.txt", "wb") as log:
        proc = subprocess.Popen(
            [*cmd, "agent.save_interval=1"], stdout=log, stderr=subprocess.STDOUT, env=_subprocess_env()
        )

        def past_the_first_iteration():  # checkpoints every iteration: model_1.pt is iteration 1 done
            assert proc.poll() is None, (tmp_path / "out.txt").read_text()[-2000:]
            return glob.glob(str(logs / "rsl_rl" / "*" / "*" / "model_1.pt"))

        wait_for(past_the_first_iteration, 120, "the training's second checkpoint")
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=60)
    out = (tmp_path / "out.txt").read_text()
    assert proc.returncode == 143, out[-2000:]
    (run,) = _runs(tmp_path)
    assert "Interrupted: saved " in out, out[-2000:]
    saved = out.split("Interrupted: saved ")[1].split()[0]
    assert os.path.dirname(saved) == run
    assert torch.load(saved, weights_only=False)["iter"] >= 1  # the iteration it was at, saved whole


def test_a_stop_whose_saved_checkpoint_meets_the_goal_ends_as_solved(tmp_path):
    """`simlab bench solve` judges each checkpoint; a stop (a budget's SIGTERM, here Ctrl+C) saves the
    iteration it is at, and when that checkpoint meets the goal the training ends there as solved.
    (It used to end with an error, and make_pretrained shipped nothing: ANYmal-C rough, 2026-11-29.)"""
    import _thread

    from simlab.cli.main import build_parser
    from simlab.cli.train import run_train

    judged = []

    def judge(path: str, iteration: int, seconds: dict[str, float]) -> bool:
        judged.append(path)
        if len(judged) == 1:
            _thread.interrupt_main()  # Ctrl+C, right after the first checkpoint
            return False
        return True  # the checkpoint saved on the way out meets the goal

    argv = ["train", *SMALL, "--library", "rsl_rl", "--max_iterations", "100000", "--log_root", str(tmp_path)]
    args = build_parser().parse_args(argv)
    args.on_checkpoint = judge
    run_dir = run_train(args, ["agent.save_interval=100000"])
    assert len(judged) == 2 and os.path.dirname(judged[1]) == run_dir and os.path.isfile(judged[1])


# --- item 8: resume continues counters and logs --------------------------------------------------


def _tensorboard_steps(run: str, tag: str) -> list[int]:
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    steps = []
    for events in glob.glob(os.path.join(run, "**", "events.out.tfevents.*"), recursive=True):
        acc = EventAccumulator(events)
        acc.Reload()
        if tag in acc.Tags()["scalars"]:
            steps += [e.step for e in acc.Scalars(tag)]
    return sorted(steps)


def test_skrl_resume_continues_the_step_counter(tmp_path):
    first = _train(tmp_path, library="skrl")
    done = max(int(os.path.basename(f)[6:-3]) for f in glob.glob(os.path.join(first, "checkpoints", "agent_*.pt")))
    ckpt = os.path.join(first, "checkpoints", f"agent_{done}.pt")
    assert done > 0
    second = _train(tmp_path, "--checkpoint", ckpt, library="skrl")
    names = sorted(os.listdir(os.path.join(second, "checkpoints")))
    assert f"agent_{2 * done}.pt" in names, names
    steps = _tensorboard_steps(second, "Reward / Instantaneous reward (mean)")
    assert steps and min(steps) > done, steps


def _policy_weights(checkpoint: str) -> dict[str, torch.Tensor]:
    if checkpoint.endswith(".zip"):  # Stable-Baselines3
        from stable_baselines3 import PPO

        return PPO.load(checkpoint, device="cpu").policy.state_dict()
    if checkpoint.endswith(".pth"):  # rl_games; its running mean normalizers learn without the optimizer
        weights = torch.load(checkpoint, map_location="cpu", weights_only=False)["model"]
        return {name: w for name, w in weights.items() if "mean_std" not in name}
    return torch.load(checkpoint, map_location="cpu", weights_only=False)["policy"]  # skrl


@pytest.mark.parametrize(
    ("library", "pattern", "learning_rate"),
    [
        ("skrl", "checkpoints/agent_*.pt", "agent.agent.learning_rate"),
        ("sb3", "model_*.zip", "agent.learning_rate"),
        ("rl_games", "nn/*.pth", "agent.params.config.learning_rate"),
    ],
)
def test_a_resumed_run_takes_the_learning_rate_it_is_given(tmp_path, library, pattern, learning_rate):
    """skrl and Stable-Baselines3 restore the saved learning rate with the checkpoint, rl_games its
    optimizer's; a rate given for the resumed run must apply (at 0 the policy may not change)."""
    first = _train(tmp_path, library=library)
    ckpt = max(glob.glob(os.path.join(first, pattern)), key=os.path.getmtime)
    second = _train(tmp_path, "--checkpoint", ckpt, f"{learning_rate}=0.0", library=library)
    resumed = max(glob.glob(os.path.join(second, pattern)), key=os.path.getmtime)
    before, after = _policy_weights(ckpt), _policy_weights(resumed)
    assert before.keys() == after.keys()
    for name in before:
        assert torch.equal(before[name], after[name]), name


def test_rsl_rl_resume_keeps_episode_lengths(tmp_path, monkeypatch):
    """A fresh run spreads its first resets over an episode; a resumed one must not (it would log short,
    untrained-looking episodes right after resuming)."""
    from rsl_rl.runners import OnPolicyRunner

    seen = []
    learn = OnPolicyRunner.learn

    def spy(self, num_learning_iterations, init_at_random_ep_len=False):
        seen.append(bool(self.env.episode_length_buf.any()) or init_at_random_ep_len)
        return learn(self, num_learning_iterations, init_at_random_ep_len)

    monkeypatch.setattr(OnPolicyRunner, "learn", spy)
    run = _train(tmp_path)
    second = _train(tmp_path, "--checkpoint", os.path.join(run, "model_1.pt"))
    assert seen == [True, False]
    assert torch.load(os.path.join(second, "model_2.pt"), weights_only=False)["iter"] == 2


# --- item 9: one place for errors ----------------------------------------------------------------


def test_errors_one_line_for_simlab_traceback_for_bugs(tmp_path, capsys, monkeypatch):
    assert _run(tmp_path, "train", *SMALL[:-1], "cuda:7") == 2
    err = capsys.readouterr().err
    assert "cuda:7" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1

    assert _run(tmp_path, "train", *SMALL[:-1], "cuda:7", "--debug") == 2
    assert "Traceback" in capsys.readouterr().err

    # a bug (here: a failing library call) keeps its traceback
    import simlab.cli.session as session

    def broken(*args, **kwargs):
        return {}["no such key"]

    monkeypatch.setattr(session, "load_cfg_from_registry", broken)
    assert _run(tmp_path, "train", *SMALL) == 1
    err = capsys.readouterr().err
    assert "Traceback" in err and "KeyError" in err


def test_error_family_keeps_builtin_bases():
    assert issubclass(ConfigError, ValueError) and issubclass(CheckpointError, ValueError)
    assert is_intended_error(ConfigError("x")) and isinstance(ConfigError("x"), SimlabError)
    try:
        int("not a number")  # raised by Python inside this test, not by a simlab raise statement
    except ValueError as e:
        assert not is_intended_error(e)
    from simlab.tasks.utils import parse_env_cfg

    with pytest.raises(ValueError) as info:
        parse_env_cfg(TASK, device="cpu", num_envs=0)
    assert is_intended_error(info.value)


def _floats(state):
    if isinstance(state, torch.Tensor):
        return [state] if state.is_floating_point() else []
    if isinstance(state, dict):
        return [t for v in state.values() for t in _floats(v)]
    return []


@pytest.mark.parametrize(
    ("library", "learning_rate", "checkpoint"),
    [
        ("rsl_rl", "agent.algorithm.learning_rate", "model_*.pt"),
        ("skrl", "agent.agent.learning_rate", "checkpoints/agent_*.pt"),
        ("sb3", "agent.learning_rate", "model_*_steps.zip"),
        ("rl_games", "agent.params.config.learning_rate", "nn/*_diverged.pth"),
    ],
)
def test_a_diverging_learner_stops_and_keeps_the_last_good_checkpoint(
    tmp_path, capsys, library, learning_rate, checkpoint
):
    argv = ["--library", library, "--max_iterations", "30", f"{learning_rate}=1e6"]
    assert _run(tmp_path, "train", *SMALL, *argv) == 2
    err = capsys.readouterr().err
    assert "Training diverged" in err and learning_rate in err and "Saved the last good weights" in err, err[-3000:]
    assert "Traceback" not in err
    (run,) = _runs(tmp_path, library)
    (saved,) = glob.glob(os.path.join(run, checkpoint))
    if library == "sb3":
        from stable_baselines3 import PPO

        weights = list(PPO.load(saved, device="cpu").policy.parameters())
    else:
        weights = _floats(torch.load(saved, weights_only=False))
    assert weights and all(torch.isfinite(w).all() for w in weights)


# --- item 11: failed starts and videos -----------------------------------------------------------


def test_a_failed_start_leaves_no_run_folder(tmp_path, capsys):
    assert _run(tmp_path, "train", *SMALL, "env.actions.joint_effort.joint_names=[no_such_joint]") == 2
    err = capsys.readouterr().err
    assert "no_such_joint" in err and "Traceback" not in err
    assert _runs(tmp_path) == []


@pytest.mark.slow  # a training and two plays, each recording video offscreen
@pytest.mark.skipif(not rendering_available(), reason="no offscreen OpenGL (install libosmesa6)")
def test_videos_no_false_warning_and_never_overwritten(tmp_path, capsys):
    video = ["--video", "--video_length", "3", "--video_interval", "8"]
    with warnings.catch_warnings(record=True) as warned:
        warnings.simplefilter("always")
        run = _train(tmp_path, *video)
        play = ["play", *SMALL, "--use_last_checkpoint", "--no_export", "--video", "--video_length", "3"]
        assert _run(tmp_path, *play) == 0
    assert not [w for w in warned if "Overwriting existing videos" in str(w.message)]
    first = glob.glob(os.path.join(run, "videos", "play", "*.mp4"))
    assert len(first) == 1
    assert _run(tmp_path, *play) == 0
    both = sorted(glob.glob(os.path.join(run, "videos", "play", "*.mp4")))
    assert len(both) == 2 and first[0] in both
    assert not glob.glob(os.path.join(run, "videos", "**", ".*"), recursive=True)  # no temporary files left


def test_multi_agent_runs_record_per_agent_sizes_and_play(tmp_path, capsys):
    task = ["--task", "simlab/Cart-Double-Pendulum-Direct-v0", "--num_envs", "4", "--device", "cpu"]
    ippo = ["--library", "skrl", "--algorithm", "IPPO"]
    assert _run(tmp_path, "train", *task, *ippo, "--max_iterations", "1") == 0
    (run,) = _runs(tmp_path, "skrl")
    info = load_yaml(os.path.join(run, "params", "run.yaml"))
    assert info["algorithm"] == "IPPO" and set(info["observations"]) == {"cart", "pendulum"}
    assert _run(tmp_path, "play", *task, *ippo, "--use_last_checkpoint", "--steps", "2", "--no_export") == 0
    # played as PPO's one agent for both (no --algorithm), the refusal names the flag that fits
    capsys.readouterr()
    assert _run(tmp_path, "play", *task, "--library", "skrl", "--use_last_checkpoint", "--steps", "2") == 2
    assert "its run trained skrl's IPPO: give --algorithm IPPO" in capsys.readouterr().err
