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
    import re

    with open(os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scripts", "setup.sh")) as f:
        extras = re.search(r'^extras="([^"]+)"', f.read(), re.M).group(1).split(",")
    assert "datasets" in extras
