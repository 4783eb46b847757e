"""The ``simlab`` command: a short train + play + export per library, resume, errors, videos, Ctrl+C."""

from __future__ import annotations

import glob
import os
import signal
import subprocess
import sys

import numpy as np
import pytest
import torch
from conftest import rendering_available, wait_for

from simlab.cli.main import main

TASK = "simlab/Cartpole-v0"
SMALL = ["--task", TASK, "--num_envs", "16", "--headless", "--device", "cpu"]
LIBRARIES = ["rsl_rl", "skrl", "sb3", "rl_games"]


def _run(tmp_path, *argv) -> int:
    return main([*argv, "--log_root", str(tmp_path / "logs")])


def _only_run(tmp_path, library):
    runs = glob.glob(str(tmp_path / "logs" / library / "*" / "*"))
    assert len(runs) == 1, runs
    return runs[0]


@pytest.mark.parametrize("library", LIBRARIES)
def test_train_play_export(tmp_path, library, monkeypatch):
    import tempfile

    # nothing is left in the temp folder (SB3's default logger would make <temp>/SB3-<date>)
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path / "tmp"))
    monkeypatch.delenv("SB3_LOGDIR", raising=False)
    (tmp_path / "tmp").mkdir()
    seed = "agent.params.seed=5" if library == "rl_games" else "agent.seed=5"
    assert _run(tmp_path, "train", *SMALL, "--library", library, "--max_iterations", "2", seed) == 0
    run = _only_run(tmp_path, library)
    for name in ("env.yaml", "agent.yaml", "command.txt"):
        assert os.path.isfile(os.path.join(run, "params", name))
    with open(os.path.join(run, "params", "command.txt")) as f:
        assert "--max_iterations 2" in f.read()
    assert glob.glob(os.path.join(run, "**", "events.out.tfevents.*"), recursive=True)

    assert _run(tmp_path, "play", *SMALL, "--library", library, "--use_last_checkpoint", "--steps", "3") == 0
    exported = glob.glob(os.path.join(run, "**", "exported"), recursive=True)
    assert len(exported) == 1
    ort = pytest.importorskip("onnxruntime")
    obs = np.random.default_rng(0).standard_normal((5, 4)).astype(np.float32)
    (onnx_actions,) = ort.InferenceSession(os.path.join(exported[0], "policy.onnx")).run(["actions"], {"obs": obs})
    jit_actions = torch.jit.load(os.path.join(exported[0], "policy.pt"))(torch.from_numpy(obs)).detach().numpy()
    assert onnx_actions.shape == (5, 1)
    np.testing.assert_allclose(onnx_actions, jit_actions, atol=1e-5)
    assert not list((tmp_path / "tmp").glob("SB3-*"))


def test_resume_continues_iterations(tmp_path):
    assert _run(tmp_path, "train", *SMALL, "--max_iterations", "2", "agent.save_interval=1") == 0
    first = _only_run(tmp_path, "rsl_rl")
    ckpt = os.path.join(first, "model_1.pt")
    assert os.path.isfile(ckpt)
    # a new run folder, even within the same second (`<time>_1`), sorted after the first
    assert _run(tmp_path, "train", *SMALL, "--max_iterations", "2", "--checkpoint", ckpt) == 0
    second = max(glob.glob(str(tmp_path / "logs" / "rsl_rl" / "*" / "*")))
    assert second != first
    saved = torch.load(os.path.join(second, "model_2.pt"), weights_only=False)
    assert saved["iter"] == 2 and "optimizer_state_dict" in saved


def test_errors_are_clear(tmp_path, capsys):
    assert _run(tmp_path, "train", "--task", "simlab/Cartpol-v0") == 2
    assert "Cartpole-v0" in capsys.readouterr().err
    assert _run(tmp_path, "play", *SMALL, "--use_last_checkpoint") == 2
    err = capsys.readouterr().err
    assert "No checkpoint" in err and "logs" in err and f"simlab train --task {TASK} --library rsl_rl" in err
    assert _run(tmp_path, "train", *SMALL, "--distributed") == 2
    assert "--distributed on the CPU needs --nproc_per_node" in capsys.readouterr().err
    assert _run(tmp_path, "train", *SMALL, "env.actions.joint_efort.scale=1") == 2
    assert "joint_effort" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        _run(tmp_path, "train", *SMALL, "--no_such_flag")


def test_a_library_the_task_has_no_agent_for_names_the_flags_it_has(tmp_path, capsys):
    # the registry's entry-point keys mean nothing on the command line: the flags that work are named
    argv = ["--task", "simlab/Shadow-Hand-Over-Direct-v0", "--num_envs", "2", "--headless", "--device", "cpu"]
    assert _run(tmp_path, "train", *argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith(
        "has no agent config for --library rsl_rl; it has: --library rl_games, --library skrl,"
        " --library skrl --algorithm IPPO, --library skrl --algorithm MAPPO."
    )
    assert _run(tmp_path, "train", *SMALL, "--library", "skrl", "--algorithm", "MAPPO") == 2
    assert (
        "it has: --library rl_games, --library rsl_rl, --agent rsl_rl_distillation_cfg_entry_point,"
        " --agent rsl_rl_with_symmetry_cfg_entry_point," in capsys.readouterr().err
    )
    assert not os.path.exists(tmp_path / "logs")  # refused before a run folder is made


def test_output_to_a_reader_that_went_away_ends_quietly():
    """`simlab list | head -1`: the pipe closes before simlab writes; no traceback, the shell's exit code."""
    command = [sys.executable, "-m", "simlab", "list"]
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    proc.stdout.close()
    err = proc.stderr.read()
    assert proc.wait(timeout=120) == 141 and err == "", err


def test_list_random_zero(tmp_path, capsys):
    assert main(["list", "--keyword", "cartpole"]) == 0
    out = capsys.readouterr().out
    assert "simlab/Cartpole-v0" in out and "simlab/Ant-Direct-v0" not in out
    assert main(["list", "GO2"]) == 0  # the word alone, in any case
    out = capsys.readouterr().out
    assert "simlab/Velocity-Rough-Unitree-Go2-v0" in out and "Cartpole" not in out
    assert main(["list", "gg1"]) == 1  # a typo: the close words, not every id
    out = capsys.readouterr().out.strip()
    assert out.startswith("No task id contains 'gg1'. Close words in the ids: ['g1'") and "Cartpole" not in out
    assert _run(tmp_path, "random", *SMALL, "--steps", "3") == 0
    assert (
        _run(
            tmp_path,
            "zero",
            "--task",
            "simlab/Cart-Double-Pendulum-Direct-v0",
            "--num_envs",
            "2",
            "--steps",
            "3",
            "--headless",
        )
        == 0
    )


def test_random_ends_after_its_steps_seeded_without_a_warning(tmp_path, capsys, caplog):
    """The README's ``simlab random`` with ``--steps`` ends by itself; without --seed it is seeded (0)."""
    direct = ["--task", "simlab/Cartpole-Direct-v0", "--num_envs", "2", "--headless", "--device", "cpu"]
    for command in ("random", "zero"):
        caplog.clear()
        assert _run(tmp_path, command, *direct, "--steps", "5") == 0
        out = capsys.readouterr().out
        assert "seed 0, 5 steps" in out and "[simlab] 5 steps done" in out, out
        assert not [r for r in caplog.records if "Seed not set" in r.getMessage()]
    assert _run(tmp_path, "random", *direct, "--steps", "1", "--seed", "-1") == 0
    assert "seed 0," not in capsys.readouterr().out  # -1 draws a seed (0 only by a 1 in 2**32 chance)


@pytest.mark.skipif(not rendering_available(), reason="no offscreen OpenGL (install libosmesa6 or an EGL driver)")
def test_train_video(tmp_path):
    assert (
        _run(
            tmp_path,
            "train",
            "--task",
            TASK,
            "--num_envs",
            "64",  # env 0 lies far from the world origin the camera looks at
            "--max_iterations",
            "1",
            "--video",
            "--video_length",
            "5",
            "--video_interval",
            "8",
            "--headless",
        )
        == 0
    )
    videos = glob.glob(os.path.join(_only_run(tmp_path, "rsl_rl"), "videos", "train", "*.mp4"))
    assert videos and os.path.getsize(videos[0]) > 0
    import imageio.v3 as iio

    frames = iio.imread(sorted(videos)[0])  # (T, H, W, 3)
    assert len(frames) == 4  # every other step drawn (60 steps/s, 30 frames/s) of gymnasium's 5 + 1 steps
    # the robots move: an empty floor (the old bug with num_envs > 1) gives identical frames
    moved = np.abs(frames[0].astype(int) - frames[-1].astype(int)).sum(axis=-1) > 30
    assert moved.mean() > 0.001


@pytest.mark.skipif(not rendering_available(), reason="no offscreen OpenGL (install libosmesa6 or an EGL driver)")
def test_videos_draw_30_frames_per_simulated_second_not_every_step(tmp_path):
    import gymnasium as gym
    import imageio.v3 as iio

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.cli.session import _RecordVideo
    from simlab.tasks.utils import load_cfg_from_registry

    cfg = load_cfg_from_registry(TASK, "env_cfg_entry_point")
    cfg.scene.num_envs, cfg.sim.device, cfg.viewer.resolution = 4, "cpu", (160, 120)
    base = gym.make(TASK, cfg=cfg, render_mode="rgb_array")
    assert base.unwrapped.metadata["render_fps"] == pytest.approx(60.0)  # a step is 1/60 s
    drawn = []
    render = base.unwrapped.render
    base.unwrapped.render = lambda: drawn.append(1) or render()
    env = _RecordVideo(base, video_folder=str(tmp_path), step_trigger=lambda step: step == 0, video_length=20)
    env.reset()
    for _ in range(30):
        env.step(torch.zeros(4, 1))
    env.close()
    (video,) = glob.glob(str(tmp_path / "*.mp4"))
    frames = iio.imread(video)
    # 20 steps (1/3 s) of video: every other step drawn, the clip at 30 frames per second
    assert len(drawn) == len(frames) == 11 and iio.immeta(video)["fps"] == pytest.approx(30.0)


def test_python_m_simlab_and_ctrl_c_saves(tmp_path):
    cmd = [
        sys.executable,
        "-m",
        "simlab",
        "train",
        *SMALL,
        "--max_iterations",
        "100000",
        "--log_root",
        str(tmp_path / "logs"),
        "agent.save_interval=1",
    ]
    with open(tmp_path / "out.txt", "wb") as log:
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT)

        def past_the_first_iteration():  # checkpoints every iteration: model_1.pt is iteration 1 done
            assert proc.poll() is None, (tmp_path / "out.txt").read_text()[-2000:]
            return glob.glob(str(tmp_path / "logs" / "rsl_rl" / "*" / "*" / "model_1.pt"))

        wait_for(past_the_first_iteration, 120, "the training's second checkpoint")
        proc.send_signal(signal.SIGINT)
        proc.wait(timeout=60)
    out = (tmp_path / "out.txt").read_text()
    assert proc.returncode == 130, out[-2000:]
    assert "Interrupted: saved " in out, out[-2000:]
    saved = out.split("Interrupted: saved ")[1].split()[0]
    assert os.path.dirname(saved) == _only_run(tmp_path, "rsl_rl")
    assert torch.load(saved, weights_only=False)["iter"] >= 1  # the iteration it was at, saved whole


def test_video_without_a_working_gl_backend_fails_before_training(tmp_path, capsys, monkeypatch):
    from simlab.utils import gl_backend

    monkeypatch.setenv("MUJOCO_GL", "bogus")
    monkeypatch.setattr(gl_backend, "_checked", {})
    assert _run(tmp_path, "train", *SMALL, "--max_iterations", "1", "--video") == 2
    err = capsys.readouterr().err
    assert "MUJOCO_GL=bogus" in err and "unset MUJOCO_GL" in err
    assert not glob.glob(str(tmp_path / "logs" / "rsl_rl" / "*" / "*" / "model_*.pt"))  # nothing was trained


def test_the_progress_bar_rate_is_steps_over_the_librarys_iteration_time():
    """The bar is made after the first iteration: its rate must come from the iterations' own times,
    or the first iteration's steps count in no time (a 1-iteration rl_games run showed 7 million steps/s)."""
    from simlab.cli.libraries.progress import ProgressBar

    bar = ProgressBar(total=3, desc="test")
    bar.update(1, steps=1000, seconds=0.5)
    bar.update(1, steps=1000, seconds=1.5)
    assert "steps/s=1,000" in bar._bar.postfix
    bar.close()
