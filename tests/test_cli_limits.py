"""Settings and files at their limits get one line and exit 2, not a traceback (issue 37, items 6, 7, 9-11)."""

from __future__ import annotations

import os
import re
import sys

import pytest

from simlab.cli.main import main

TASK = "simlab/Cartpole-v0"
SMALL = ["--task", TASK, "--num_envs", "8", "--headless", "--device", "cpu"]


def _run(tmp_path, *argv) -> int:
    return main([*argv, "--log_root", str(tmp_path / "logs")])


def _one_line_error(capsys, after_progress: bool = False) -> str:
    """The error line, checked to be the only line on stderr (or, ``after_progress``, the only line after
    a progress bar's, on a line of its own)."""
    err = capsys.readouterr().err
    if after_progress:
        *bar, err = err.rstrip("\n").split("\n")
        assert all(line.lstrip("\r").startswith("rsl_rl:") for line in bar), bar
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    assert err.startswith("simlab "), err
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


# --- item 7: overrides and env counts that used to end in a traceback ------------------------------


@pytest.mark.parametrize(
    ("flags", "message"),
    [
        (
            ["env.observations.policy=null"],
            "env.observations.policy is None: the learner reads the 'policy' observation",
        ),
        (["env.observations=null"], "env.observations.policy is None"),
        (
            ["env.episode_length_s=${env.nope}"],
            "'env.episode_length_s=${env.nope}': Interpolation key 'env.nope' not found",
        ),
    ],
)
def test_overrides_that_break_the_env_are_one_line(tmp_path, capsys, flags, message):
    assert _run(tmp_path, "train", *SMALL, "--max_iterations", "1", *flags) == 2
    assert message in _one_line_error(capsys)
    assert not os.path.exists(tmp_path / "logs")


def test_play_refuses_a_removed_policy_group_too(tmp_path, capsys):
    assert _run(tmp_path, "play", *SMALL, "--use_last_checkpoint", "env.observations.policy=null") == 2
    assert "env.observations.policy is None" in _one_line_error(capsys)


def test_more_envs_than_memory_holds_are_refused_before_allocating(tmp_path, capsys, monkeypatch):
    import simlab.sim.backends.cpu as cpu

    monkeypatch.setattr(cpu, "available_memory", lambda: 64 * 2**20)
    allocated = []
    monkeypatch.setattr(cpu.mjbatch, "Batch", lambda *args, **kwargs: allocated.append(args))
    assert _run(tmp_path, "train", *SMALL[:2], "--num_envs", "100000", *SMALL[4:], "--max_iterations", "1") == 2
    err = _one_line_error(capsys)
    assert not allocated
    # the cartpole's MjData holds 6592 bytes
    needed = float(
        re.search(r"100000 envs need about (\d+\.\d) MiB of memory \(6\.4 KiB per env for this model\)", err)[1]
    )
    assert 628.7 < needed < 628.7 + 16 * 14  # and each worker thread's MjData with its 13 MiB arena
    assert "but 64.0 MiB is available" in err
    fits = int(err.split("at most about ")[1].split()[0])
    assert 0 < fits < 64 * 2**20 // 6592  # less the worker threads' own MjData and arena
    assert err.rstrip().endswith("envs fit (--num_envs or env.scene.num_envs).")


_ENV_MEMORY = """
import sys, gymnasium as gym, mujoco, torch
import simlab.tasks
from simlab.tasks.utils import parse_env_cfg
def rss():
    return int(open("/proc/self/statm").read().split()[1]) * 4096
task, n = sys.argv[1], int(sys.argv[2])
cfg = parse_env_cfg(task, device="cpu", num_envs=n)
before = rss()
env = gym.make(task, cfg=cfg)
env.reset()
for _ in range(3):
    env.step(torch.zeros((n, *env.unwrapped.single_action_space.shape)))
print(rss() - before, mujoco.MjData(env.unwrapped.sim.model).nbuffer)
"""


@pytest.mark.slow
@pytest.mark.skipif(not os.path.exists("/proc/self/statm"), reason="reads the resident memory from /proc")
def test_the_memory_estimate_covers_what_an_env_holds_per_world():
    """The estimate counts one MjData per world; an env of the CPU backend holds less (measured per world
    as the growth of the resident memory from 256 to 2304 envs, in fresh processes)."""
    import subprocess
    import sys

    grown = []
    for n in (256, 2304):
        out = subprocess.run(
            [sys.executable, "-c", _ENV_MEMORY, TASK, str(n)], capture_output=True, text=True, check=True
        )
        used, per_world = (int(v) for v in out.stdout.split()[-2:])
        grown.append(used)
    measured = (grown[1] - grown[0]) / 2048
    assert 0 < measured < per_world, (measured, per_world)


# --- item 9: a log folder that cannot be written, a full disk, a writer killed mid-write -----------


def _as_root() -> bool:
    return hasattr(os, "geteuid") and os.geteuid() == 0


def test_a_log_root_under_a_file_is_one_line(tmp_path, capsys):
    (tmp_path / "file").write_text("not a folder")
    argv = ["train", *SMALL, "--max_iterations", "1", "--log_root", str(tmp_path / "file" / "logs")]
    assert main(argv) == 2
    err = _one_line_error(capsys)
    assert f"Cannot create a run folder in '{tmp_path / 'file' / 'logs' / 'rsl_rl' / 'cartpole'}'" in err
    assert "Give a --log_root you can write." in err


@pytest.mark.skipif(_as_root() or os.name != "posix", reason="root writes into read-only folders")
def test_a_read_only_log_root_is_one_line(tmp_path, capsys):
    logs = tmp_path / "logs"
    logs.mkdir()
    logs.chmod(0o500)
    try:
        assert main(["train", *SMALL, "--max_iterations", "1", "--log_root", str(logs)]) == 2
    finally:
        logs.chmod(0o700)
    err = _one_line_error(capsys)
    assert "Cannot create a run folder in" in err and "Permission denied" in err


def test_a_read_only_log_root_is_one_line_as_root_too(tmp_path, capsys, monkeypatch):
    """As root chmod stops no write: the folder refuses through os.mkdir, as a read-only mount does."""
    import errno

    import simlab.cli.runs as runs

    def mkdir(path, *args, **kwargs):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS), path)

    monkeypatch.setattr(runs.os, "mkdir", mkdir)  # os.makedirs creates its folders with os.mkdir too
    assert _run(tmp_path, "train", *SMALL, "--max_iterations", "1") == 2
    assert "Cannot create a run folder in" in _one_line_error(capsys)


def _files(folder) -> dict[str, bytes]:
    return {name: (folder / name).read_bytes() for name in os.listdir(folder) if (folder / name).is_file()}


def test_a_full_disk_during_training_keeps_the_last_checkpoint_and_no_temporary_file(tmp_path, capsys, monkeypatch):
    import errno

    import torch

    saved: dict[str, bytes] = {}
    real_save = torch.save

    def save(obj, f, *args, **kwargs):
        run = os.path.dirname(f)
        saved.update({k: v for k, v in _files(type(tmp_path)(run)).items() if k.startswith("model_")})
        if saved:  # the second checkpoint: the disk fills up halfway through
            with open(f, "wb") as out:
                out.write(b"\0" * 1000)
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        real_save(obj, f, *args, **kwargs)

    monkeypatch.setattr(torch, "save", save)
    assert _run(tmp_path, "train", *SMALL, "--max_iterations", "3", "agent.save_interval=1") == 2
    err = _one_line_error(capsys, after_progress=True)
    (run,) = (tmp_path / "logs" / "rsl_rl" / "cartpole").iterdir()
    assert f"Cannot write 'model_1.pt' into '{run}': No space left on device" in err
    assert f"Training stopped; its last complete checkpoint is '{run / 'model_0.pt'}'." in err
    assert list(saved) == ["model_0.pt"] and _files(run)["model_0.pt"] == saved["model_0.pt"]
    assert not [name for name in os.listdir(run) if ".tmp" in name]


@pytest.mark.parametrize("main_thread_fails", [True, False])
def test_a_background_writer_on_a_full_disk_prints_no_traceback(capsys, main_thread_fails):
    """TensorBoard's event writer dies in its own thread and raises again in the command's thread."""
    import errno
    import threading

    from simlab.cli.main import _run_command

    def command() -> int:
        def write():
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

        thread = threading.Thread(target=write)
        thread.start()
        thread.join()
        if main_thread_fails:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), "/run/events.out.tfevents")
        return 0

    assert _run_command("train", False, command) == (2 if main_thread_fails else 0)
    err = capsys.readouterr().err
    assert "Traceback" not in err and "Exception in thread" not in err and len(err.strip().splitlines()) == 1
    if main_thread_fails:
        assert err == "simlab train: error: [Errno 28] No space left on device: '/run/events.out.tfevents'\n"
    else:
        assert err == "[simlab] WARNING: a background writer stopped: [Errno 28] No space left on device\n"


_SLOW_WRITER = """
import sys, time
from simlab.utils.io import atomic_path
with atomic_path(sys.argv[1]) as tmp, open(tmp, "wb") as f:
    f.write(b"new" * 1000)
    f.flush()
    print("writing", flush=True)
    time.sleep(120)
"""


def test_a_writer_killed_mid_write_leaves_the_old_file_and_its_temporary_file_is_removed(tmp_path):
    import signal
    import subprocess
    import sys

    import torch

    from simlab.cli.checkpoints import resolve_checkpoint

    old = tmp_path / "model_1.pt"
    torch.save({"w": torch.ones(3)}, old)
    before = old.read_bytes()
    env = {**os.environ, "PYTHONPATH": os.path.dirname(os.path.dirname(os.path.abspath(__file__)))}
    writer = subprocess.Popen([sys.executable, "-c", _SLOW_WRITER, str(old)], stdout=subprocess.PIPE, env=env)
    try:
        assert writer.stdout.readline() == b"writing\n"
    finally:
        writer.send_signal(signal.SIGKILL)
        writer.wait(timeout=30)
    left = [name for name in os.listdir(tmp_path) if ".tmp" in name]
    assert left == [f".model_1.pt.{writer.pid}.tmp"]  # what the kill left
    assert old.read_bytes() == before
    # the next look for checkpoints in the folder (play, resume) removes it
    assert resolve_checkpoint(str(tmp_path), "rsl_rl") == str(old)
    assert os.listdir(tmp_path) == ["model_1.pt"] and old.read_bytes() == before


@pytest.mark.skipif(not _as_root() or not sys.platform.startswith("linux"), reason="mounts a small tmpfs")
def test_a_really_full_disk_during_training(tmp_path, capsys):
    """torch reports a failed write as a RuntimeError without its cause: simlab finds the full disk."""
    import subprocess

    disk = tmp_path / "disk"
    disk.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", str(disk)], capture_output=True).returncode:
        pytest.skip("cannot mount a tmpfs here")
    try:
        argv = ["train", *SMALL, "--max_iterations", "30", "agent.save_interval=1", "--log_root", str(disk)]
        assert main(argv) == 2
        err = _one_line_error(capsys, after_progress=True)
        (run,) = (disk / "rsl_rl" / "cartpole").iterdir()
        assert f"into '{run}': No space left on device" in err and "its last complete checkpoint is" in err
        last = err.split("its last complete checkpoint is '")[1].split("'")[0]
        import torch

        torch.load(last, weights_only=True)  # complete
        assert not [name for name in os.listdir(run) if ".tmp" in name]
    finally:
        subprocess.run(["umount", str(disk)], check=True)


# --- items 10 and 11: HDF5 datasets ---------------------------------------------------------------


def _h5py():
    return pytest.importorskip("h5py")


@pytest.fixture(scope="module")
def recorded(tmp_path_factory) -> str:
    """One recorded episode of the cartpole (seeded random actions)."""
    path = str(tmp_path_factory.mktemp("demos") / "demos.hdf5")
    argv = ["record", "--task", TASK, "--num_envs", "1", "--device", "cpu", "--headless", "--dataset_file", path]
    assert main(argv) == 0
    return path


def _replay(path, *flags) -> int:
    return main(["replay", "--task", TASK, "--device", "cpu", "--headless", "--dataset_file", str(path), *flags])


def test_a_recording_stores_its_task_and_replay_refuses_another(recorded, capsys):
    from simlab.utils.datasets import HDF5DatasetFileHandler

    handler = HDF5DatasetFileHandler()
    handler.open(recorded)
    assert handler.get_env_name() == TASK
    handler.close()
    capsys.readouterr()
    assert _replay(recorded, "--validate_states") == 0
    assert "states bit-identical" in capsys.readouterr().out

    argv = ["replay", "--task", "simlab/Reach-Franka-v0", "--device", "cpu", "--dataset_file", recorded]
    assert main(argv) == 2
    err = _one_line_error(capsys)
    assert f"holds episodes of {TASK}, not simlab/Reach-Franka-v0: replay it with --task {TASK}" in err


def _write(path, build) -> str:
    h5py = _h5py()
    with h5py.File(path, "w") as f:
        build(f)
    return str(path)


def _episode(f, actions_shape=(5, 1), name="demo_0", **create):
    group = f.require_group("data").create_group(name)
    group.create_dataset("actions", shape=actions_shape, **{"dtype": "float32", **create})
    for key, width in (("joint_position", 2), ("joint_velocity", 2), ("root_pose", 7), ("root_velocity", 6)):
        group.create_dataset(f"initial_state/articulation/robot/{key}", data=[[0.0] * width])
    return group


def test_an_unnamed_file_of_another_task_is_refused_by_its_action_width(tmp_path, capsys):
    path = _write(tmp_path / "other.hdf5", lambda f: _episode(f, actions_shape=(5, 3), data=[[0.0] * 3] * 5))
    assert _replay(path) == 2
    assert "demo_0 has actions of width 3; this task's are 1 wide" in _one_line_error(capsys)


def test_a_declared_shape_larger_than_the_stored_data_is_refused_before_reading(tmp_path, capsys):
    # 10^12 rows of gzip chunks that were never written: a few KiB on disk, 3.6 TiB if read
    path = _write(
        tmp_path / "huge.hdf5", lambda f: _episode(f, actions_shape=(10**12, 1), chunks=(1024, 1), compression="gzip")
    )
    assert os.path.getsize(path) < 100_000
    assert _replay(path) == 2
    err = _one_line_error(capsys)
    assert "declares shape (1000000000000, 1) (3.6 TiB) but the file stores 0 B for it" in err


def test_episodes_larger_than_the_free_memory_are_refused(tmp_path, monkeypatch):
    import simlab.utils.datasets.hdf5_dataset_file_handler as module

    path = _write(tmp_path / "big.hdf5", lambda f: _episode(f, data=[[0.5]] * 5))
    monkeypatch.setattr(module, "available_memory", lambda: 10)
    handler = module.HDF5DatasetFileHandler()
    handler.open(path)
    with pytest.raises(ValueError, match=r"demo_0 holds 1\d\d B of data, more than the 10 B of memory available"):
        handler.load_episode("demo_0", "cpu")
    handler.close()


@pytest.mark.parametrize(
    ("build", "message"),
    [
        (None, "is not a readable HDF5 file (Unable to"),
        (lambda f: f.create_group("episodes"), "is not an episode dataset: it has no 'data' group"),
        (lambda f: f.create_dataset("data", data=[1, 2]), "is not an episode dataset: it has no 'data' group"),
        (lambda f: f.create_group("data").attrs.update(env_args="{not json"), "its data/env_args is not a JSON object"),
        (lambda f: f.create_group("data").create_dataset("demo_0", data=[1]), "demo_0 is not an episode"),
        (lambda f: _episode(f, data=[["a"]] * 5, dtype=_h5py().string_dtype()), "/data/demo_0/actions holds object"),
        (lambda f: f.create_group("data").create_group("demo_0"), "demo_0 is not a recorded episode: it needs"),
    ],
)
def test_garbage_dataset_files_get_one_line(tmp_path, capsys, build, message):
    path = tmp_path / "garbage.hdf5"
    if build is None:
        path.write_bytes(bytes(range(256)) * 16)
    else:
        _write(path, build)
    assert _replay(path) == 2
    assert message in _one_line_error(capsys)


def test_a_truncated_dataset_file_gets_one_line(recorded, tmp_path, capsys):
    with open(recorded, "rb") as f:
        data = f.read()
    path = tmp_path / "cut.hdf5"
    path.write_bytes(data[: len(data) * 2 // 3])
    assert _replay(path) == 2
    err = _one_line_error(capsys)
    assert "cut.hdf5" in err and ("truncated or corrupt" in err or "not a readable HDF5 file" in err)


@pytest.mark.parametrize("command", ["record", "replay"])
def test_without_h5py_record_and_replay_say_how_to_install_it(tmp_path, capsys, monkeypatch, command):
    import sys

    monkeypatch.setitem(sys.modules, "h5py", None)  # import h5py raises ImportError
    monkeypatch.delitem(sys.modules, "simlab.utils.datasets.hdf5_dataset_file_handler", raising=False)
    argv = [command, "--task", TASK, "--device", "cpu", "--dataset_file", str(tmp_path / "d.hdf5")]
    assert main(argv) == 2
    assert 'need h5py: pip install "simlab[datasets]"' in _one_line_error(capsys)
    assert not os.path.exists(tmp_path / "d.hdf5")


def test_the_main_install_includes_the_datasets_extra():
    """The README's first command is `bash scripts/setup.sh`; `simlab record` / `replay` need h5py."""
    with open(os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scripts", "setup.sh")) as f:
        extras = re.search(r'^extras="([^"]+)"', f.read(), re.M).group(1).split(",")
    assert "datasets" in extras
