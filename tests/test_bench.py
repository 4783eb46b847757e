"""`simlab bench` runs end to end on the CPU and prints its tables (figures are not asserted)."""

from __future__ import annotations

import json

import pytest
from conftest import rendering_available

from simlab.benchmarks.cli import main


def test_bench_physics_and_env_print_tables_and_json(tmp_path, capsys):
    out = tmp_path / "bench.json"
    code = main(
        [
            "physics",
            "env",
            "--device",
            "cpu",
            "--robots",
            "cartpole",
            "--tasks",
            "simlab/Cartpole-Direct-v0",
            "--num_envs",
            "16",
            "--steps",
            "3",
            "--json",
            str(out),
        ]
    )
    assert code == 0
    printed = capsys.readouterr().out
    assert "scene/raw" in printed and "env/raw" in printed
    results = json.loads(out.read_text())["results"]
    physics, env = results["physics"][0], results["env"][0]
    assert "error" not in physics and "error" not in env
    assert physics["raw_steps_per_s"] > 0 and physics["scene_steps_per_s"] > 0
    assert env["env_steps_per_s"] > 0 and env["cuda_graph"] == "off"
    assert env["physics_steps_per_s"] == env["env_steps_per_s"] * 2  # cartpole decimation
    # the physics of an env step (2 raw steps) and the rest: the share outside physics follows the ratio
    assert env["physics_ms_per_env_step"] > 0
    assert env["outside_physics_share"] == pytest.approx(1.0 - env["ratio"])
    assert "outside physics" in printed
    # and timed directly, the physics left out
    assert env["outside_ms_per_step"] > 0
    assert env["outside_physics_share_timed"] == pytest.approx(env["outside_ms_per_step"] / env["env_ms_per_step"])
    assert "outside (timed)" in printed


def test_bench_env_times_the_step_without_its_physics():
    """The timed share outside the physics steps the env with MuJoCo's step left out (the rest runs)."""
    from simlab.benchmarks import env_suites

    env = env_suites.make_env("simlab/Cartpole-Direct-v0", 4, "cpu")
    env.reset()
    calls, physics_step = [], env.sim.physics._step
    env.sim.physics._step = lambda *args: calls.append(args) or physics_step(*args)
    step = env_suites._step_fn(env)
    step()
    assert calls, "the env step runs the physics"
    calls.clear()
    versions = env.sim.physics.state_version
    assert env_suites._seconds_without_physics(env, step, 3, "cpu") > 0
    assert calls == [] and env.sim.physics.state_version > versions  # stepped, without MuJoCo's step
    env.close()


def test_a_failed_step_without_physics_keeps_the_row(monkeypatch, capsys):
    """The timed share is measured last; if it fails, the row keeps its other figures and says why."""
    from simlab.benchmarks import env_suites

    def fails(*args):
        raise RuntimeError("capture failed\nmore")

    monkeypatch.setattr(env_suites, "_seconds_without_physics", fails)
    row = env_suites.bench_env("simlab/Cartpole-Direct-v0", num_envs=4, device="cpu", steps=2)
    assert row["env_steps_per_s"] > 0 and row["outside_physics_share"] is not None
    assert row["outside_timed_error"] == "RuntimeError: capture failed"
    assert "outside_physics_share_timed" not in row
    assert "the step without its physics failed: RuntimeError: capture failed" in capsys.readouterr().err


def test_bench_env_builds_each_task_with_the_env_overrides(tmp_path):
    """`--overrides env.x=v` changes the benched env (an A/B of a setting): Cartpole's decimation 2 made 3,
    seen in the physics steps per env step; agent.* ones do not reach the env suites."""
    out = tmp_path / "bench.json"
    argv = ["env", "--device", "cpu", "--tasks", "simlab/Cartpole-v0", "--num_envs", "4", "--steps", "2"]
    assert main([*argv, "--overrides", "env.decimation=3", "agent.seed=5", "--json", str(out)]) == 0
    (row,) = json.loads(out.read_text())["results"]["env"]
    assert row["overrides"] == "env.decimation=3"
    assert row["physics_steps_per_s"] == pytest.approx(row["env_steps_per_s"] * 3)


def test_bench_train_runs_the_ppo_update_asked_for(tmp_path):
    rows = {}
    for update in ("fast", "rsl_rl"):
        out = tmp_path / f"{update}.json"
        argv = ["train", "--device", "cpu", "--tasks", "simlab/Cartpole-v0", "--num_envs", "16", "--iterations", "1"]
        argv += ["--ppo_update", update]
        assert main([*argv, "--json", str(out)]) == 0
        (rows[update],) = json.loads(out.read_text())["results"]["train"]
    assert rows["fast"]["ppo_update"] == "fast" and rows["fast"]["env_steps_per_s"] > 0
    assert rows["rsl_rl"]["ppo_update"] == "rsl_rl" and rows["rsl_rl"]["rollout_policy"] == "eager"


def test_bench_refuses_bad_input_before_measuring(capsys):
    from simlab.cli.main import main as simlab_main

    assert simlab_main(["bench", "env", "--device", "cpu", "--tasks", "simlab/Cartpol-v0", "--num_envs", "8"]) == 2
    err = capsys.readouterr().err
    assert "Unknown task 'simlab/Cartpol-v0'" in err and "simlab/Cartpole-v0" in err and "Traceback" not in err
    for bad in (["physics", "--robots", "cartpol"], ["env", "--num_envs", "0"], ["env", "--steps", "0"]):
        with pytest.raises(SystemExit) as stopped:
            main([*bad, "--device", "cpu"])
        assert stopped.value.code == 2, bad
    err = capsys.readouterr().err
    assert "invalid choice: 'cartpol' (choose from 'cartpole', 'ant', 'humanoid')" in err
    assert "--num_envs takes counts >= 1" in err and "--steps takes a count >= 1" in err


def test_a_failed_measurement_is_a_row_and_a_failing_exit_code(monkeypatch, capsys):
    from simlab.benchmarks import env_suites

    def out_of_memory(*args, **kwargs):
        raise RuntimeError("CUDA out of memory (pretend)")

    monkeypatch.setattr(env_suites, "bench_env", out_of_memory)
    assert main(["env", "--device", "cpu", "--tasks", "simlab/Cartpole-v0", "--num_envs", "8"]) == 1
    captured = capsys.readouterr()
    assert "CUDA out of memory (pretend)" in captured.out
    assert "1 measurement(s) failed" in captured.err


@pytest.mark.parametrize(
    ("argv", "printed"),
    [
        (["raycast", "--num_envs", "2", "--rounds", "1", "--casts", "2"], "binned cast"),
        (["postconstraint", "--device", "cpu", "--num_envs", "2", "--steps", "2", "--rounds", "1"], "run when read"),
        (["ops", "update", "--task", "simlab/Cartpole-v0", "--device", "cpu", "--num_envs", "8"], "aten."),
        (["ops", "sync", "--device", "cpu", "--num_envs", "8", "--iterations", "1", "--rounds", "1"], "env steps/s"),
        (["startup", "--device", "cpu", "--runs", "1", "--num_envs", "16", "--top", "3"], "first iteration per run"),
        pytest.param(["terrain", "--steps", "20", "--rounds", "1"], "height_field", marks=pytest.mark.slow),
        pytest.param(
            ["viewer", "--device", "cpu", "--tasks", "simlab/Cartpole-v0", "--num_envs", "16", "--iterations", "5"]
            + ["--repeats", "1", "--log_root", "{tmp}"],
            "client received",
            marks=pytest.mark.slow,
        ),
    ],
)
def test_the_part_cost_tools_run_as_bench_subcommands(argv, printed, tmp_path, capsys):
    assert main([a.replace("{tmp}", str(tmp_path)) for a in argv]) == 0
    assert printed in capsys.readouterr().out


@pytest.mark.skipif(not rendering_available(), reason="no offscreen OpenGL (install libosmesa6 or an EGL driver)")
def test_bench_video_counts_the_frames_each_recording_draws(capsys):
    assert main(["video", "--num_envs", "2", "--steps", "4", "--repeats", "1"]) == 0
    rows = [line.split("|") for line in capsys.readouterr().out.splitlines() if line.count("|") == 5]
    drawn = {cells[1].strip(): cells[4].strip() for cells in rows}
    # the cartpole steps at 60 Hz: gymnasium draws each of the 4 steps, simlab every other one
    assert drawn == {"run": "frames drawn", "---": "---", "no video": "0", "gymnasium RecordVideo": "4",
                     "simlab --video": "2"}  # fmt: skip


def test_bench_ops_names_its_counters(capsys):
    assert main(["ops", "nope"]) == 2
    assert "give one of ['step', 'update', 'sync'] (got nope)" in capsys.readouterr().err


def test_bench_env_steps_a_multi_agent_task():
    """A multi-agent env (no single action space) gets every agent's random actions side by side."""
    from simlab.benchmarks.env_suites import bench_env

    row = bench_env("simlab/Cart-Double-Pendulum-Direct-v0", num_envs=4, device="cpu", steps=5)
    assert row["env_steps_per_s"] > 0
