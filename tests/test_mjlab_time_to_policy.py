"""scripts/benchmarks/mjlab_time_to_policy.py: mjlab's time to policy, judged as simlab's.

Without mjlab (CI): a stand-in trainer prints its iterations through rsl_rl's own Logger and saves
checkpoints as mjlab's train does; the script's timing, parsing and criteria are checked on that.
With mjlab importable, the script trains and plays mjlab's cartpole for a few iterations on the CPU.
"""

from __future__ import annotations

import inspect
import json
import math
import os
import subprocess
import sys
import textwrap
from pathlib import Path
from types import SimpleNamespace

import pytest
import torch
from conftest import load_script

from simlab.tasks.manager_based.locomotion.velocity.criterion import (
    BIPED_MAX_FALL_RATE,
    BIPED_MAX_SPEED_ERROR,
    BIPED_MAX_YAW_RATE_ERROR,
    biped_tracks_velocity,
    tracks_velocity,
)
from simlab.tasks.utils.criteria import pole_upright

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "benchmarks" / "mjlab_time_to_policy.py"


def _load_script():
    return load_script(SCRIPT)


ttp = _load_script()

# Prints as mjlab's train does (its log directory, rsl_rl's iteration block) and saves
# model_<it>.pt every iteration after sleeping the collection and learning times it reports.
STAND_IN_TRAINER = textwrap.dedent(
    """
    import sys, time
    from pathlib import Path
    import torch
    from rsl_rl.utils.logger import Logger

    run_dir, iterations, startup_s, collect_s, learn_s = Path(sys.argv[1]), int(sys.argv[2]), *map(float, sys.argv[3:6])
    run_dir.mkdir(parents=True)
    print(f"[INFO] Logging experiment in directory: {run_dir}", flush=True)
    time.sleep(startup_s)
    cfg = {"num_steps_per_env": 8, "algorithm": {"rnd_cfg": None}, "logger": "tensorboard"}
    logger = Logger(str(run_dir), cfg, {}, 4, False, 1, 0, "cpu")
    logger.init_logging_writer()
    for it in range(iterations):
        time.sleep(collect_s + learn_s)
        logger.log(it=it, start_it=0, total_it=iterations, collect_time=collect_s, learn_time=learn_s,
                   loss_dict={"value": 0.1}, learning_rate=1e-3, action_std=torch.ones(1), rnd_weight=None)
        torch.save({"iter": it}, run_dir / f"model_{it}.pt")
    """
)


def _stand_in(
    tmp_path: Path, iterations: int = 3, startup_s: float = 0.4, collect_s: float = 0.1, learn_s: float = 0.05
):
    script = tmp_path / "stand_in_trainer.py"
    script.write_text(STAND_IN_TRAINER)
    run_dir = tmp_path / "logs" / "run"
    return [sys.executable, str(script), str(run_dir), str(iterations), str(startup_s), str(collect_s), str(learn_s)]


def test_timeline_from_a_trainer_printing_through_rsl_rls_logger(tmp_path):
    argv = _stand_in(tmp_path, iterations=3, startup_s=0.4, collect_s=0.1, learn_s=0.05)
    start, code, lines = ttp.run_training(
        argv, ttp.child_environment("cpu"), str(tmp_path), str(tmp_path / "t.log"), None
    )
    assert code == 0
    log = ttp.parse_training_output(lines)
    assert log.run_dir == str(tmp_path / "logs" / "run")
    assert sorted(log.iterations) == [0, 1, 2]
    assert all(it.collection_s == 0.1 and it.learning_s == 0.05 for it in log.iterations.values())
    assert log.shares_until(1) == pytest.approx((0.2, 0.1))
    # start-up: interpreter, imports and the 0.4 s sleep; iteration 0's own 0.15 s is not in it
    assert 0.4 <= log.startup_s(start) < log.iterations[0].logged_at - start - 0.1

    checkpoints = ttp.find_checkpoints(log.run_dir)
    assert [c.iteration for c in checkpoints] == [0, 1, 2]
    assert start < checkpoints[0].written_at < checkpoints[1].written_at < checkpoints[2].written_at
    # the second checkpoint passes: time to policy is its write time from the process start
    evaluated = [ttp.Evaluated(c, s, p) for c, (s, p) in zip(checkpoints, [(0.1, False), (0.96, True), (0.99, True)])]
    row = ttp.summarize("Mjlab-Cartpole-Balance", start, log, evaluated, 16)
    assert row["solved"] and row["checkpoint"] == "model_1.pt" and row["iterations"] == 2
    assert row["time_to_policy_s"] == pytest.approx(checkpoints[1].written_at - start)
    assert row["rollout_s"] + row["update_s"] == pytest.approx(0.3)
    assert row["startup_s"] + row["rollout_s"] + row["update_s"] + row["other_s"] == pytest.approx(
        row["time_to_policy_s"]
    )
    assert "time to policy" in ttp.format_summary(row, ttp.PoleUpright.description)

    unsolved = ttp.summarize(
        "Mjlab-Cartpole-Balance", start, log, [ttp.Evaluated(c, 0.5, False) for c in checkpoints], 16
    )
    assert not unsolved["solved"] and unsolved["time_to_policy_s"] is None and unsolved["checkpoint"] == "model_2.pt"
    assert "NOT solved" in ttp.format_summary(unsolved, ttp.PoleUpright.description)


def _light_trainer(tmp_path: Path, iterations: int, seconds_each: float) -> list[str]:
    """A trainer without torch to import (it starts at once): mjlab's log-directory line, then an
    iteration line and a saved ``model_<it>.pt`` every ``seconds_each``."""
    script = tmp_path / "light_trainer.py"
    script.write_text(
        textwrap.dedent(
            f"""
            import time
            from pathlib import Path
            run_dir = Path({str(tmp_path / "run")!r}); run_dir.mkdir()
            print(f"[INFO] Logging experiment in directory: {{run_dir}}", flush=True)
            for it in range({iterations}):
                time.sleep({seconds_each})
                print(f"Learning iteration {{it}}/{iterations}", flush=True)
                (run_dir / f"model_{{it}}.pt").write_text("saved")
            """
        )
    )
    return [sys.executable, str(script)]


def test_time_budget_stops_training_and_keeps_its_checkpoints(tmp_path, capsys):
    argv, env = _light_trainer(tmp_path, 1000, 0.1), ttp.child_environment("cpu")
    start, code, lines = ttp.run_training(argv, env, str(tmp_path), str(tmp_path / "t.log"), 1.5)
    assert code == -15  # SIGTERM from the budget
    log = ttp.parse_training_output(lines)
    saved = ttp.find_checkpoints(log.run_dir)
    assert 1 <= len(saved) < 1000 and max(log.iterations) < 999
    assert all(c.written_at - start < 10 for c in saved)
    assert capsys.readouterr().out.count("time budget 2 s spent") == 1


def test_main_trains_then_plays_every_checkpoint(tmp_path, monkeypatch, capsys):
    """The flow of main with a stand-in trainer and a player that returns given verdicts."""
    played: list[list[int]] = []

    def play(task, checkpoints, device, eval_envs, eval_seconds, seed):
        played.append([c.iteration for c in checkpoints])
        assert (device, eval_envs, eval_seconds, seed) == ("cpu", 64, 5.0, 42)
        return [(0.5, False), (0.97, True), (0.98, True)]

    monkeypatch.setattr(ttp, "train_command", lambda *args: _light_trainer(tmp_path, 3, 0.05))
    monkeypatch.setattr(ttp, "play_checkpoints", play)
    assert ttp.main(["Mjlab-Cartpole-Balance", "--device", "cpu", "--out", str(tmp_path / "out")]) == 0
    assert played == [[0, 1, 2]]
    row = json.loads((tmp_path / "out" / "Mjlab-Cartpole-Balance" / "result.json").read_text())
    assert (
        row["solved"]
        and row["checkpoint"] == "model_1.pt"
        and [c["passed"] for c in row["checkpoints"]] == [False, True, True]
    )
    printed = capsys.readouterr().out
    assert "[mjlab] model_0.pt (1 iterations)" in printed and "time to policy" in printed


def test_main_reports_a_failed_training_with_its_output(tmp_path, monkeypatch, capsys):
    failing = tmp_path / "failing.py"
    failing.write_text("print('tyro: unrecognized option --agent.bogus'); raise SystemExit(2)\n")
    monkeypatch.setattr(ttp, "train_command", lambda *args: [sys.executable, str(failing)])
    assert ttp.main(["Mjlab-Cartpole-Balance", "--device", "cpu", "--out", str(tmp_path / "out")]) == 1
    assert "exited with code 2" in capsys.readouterr().err


def test_train_command_uses_mjlabs_flags():
    argv = ttp.train_command("Mjlab-Cartpole-Balance", 4096, 150, 10, "/tmp/logs", 42)
    assert argv[1:4] == ["-m", "mjlab.scripts.train", "Mjlab-Cartpole-Balance"]
    flags = dict(zip(argv[4::2], argv[5::2]))
    assert flags == {
        "--env.scene.num-envs": "4096",
        "--agent.max-iterations": "150",
        "--agent.save-interval": "10",
        "--agent.logger": "tensorboard",
        "--agent.seed": "42",
        "--log-root": "/tmp/logs",
    }
    assert "--env.scene.num-envs" not in ttp.train_command("Mjlab-Cartpole-Balance", None, 150, 10, "/tmp/logs", 42)
    assert ttp.child_environment("cpu")["CUDA_VISIBLE_DEVICES"] == ""


def _cartpole_env(angles: list[float]):
    cart = SimpleNamespace(joint_names=("slider",), data=SimpleNamespace(joint_pos=torch.zeros(len(angles), 1)))
    joint_pos = torch.stack([torch.zeros(len(angles)), torch.tensor(angles)], dim=1)
    pole = SimpleNamespace(joint_names=("slider", "hinge_1"), data=SimpleNamespace(joint_pos=joint_pos))
    return SimpleNamespace(scene=SimpleNamespace(entities={"terrain": cart, "cartpole": pole}))


def test_pole_upright_counts_wrapped_angles_and_passes_at_95_percent():
    judge = ttp.PoleUpright()
    judge.observe(_cartpole_env([0.1, -0.19, 0.3, 2 * math.pi + 0.05]))  # a full turn is upright again
    assert judge.verdict() == (0.75, False)
    judge = ttp.PoleUpright()
    for step in range(20):
        judge.observe(_cartpole_env([0.0] * 3 + [0.5 if step == 0 else 0.0]))  # 79 of 80 inside
    score, passed = judge.verdict()
    assert score == pytest.approx(79 / 80) and passed
    judge = ttp.PoleUpright()
    judge.observe(_cartpole_env([0.0] * 19 + [0.25, 0.25]))  # 19 of 21: below 95 %
    assert not judge.verdict()[1]
    with pytest.raises(RuntimeError, match="no_such_joint"):
        ttp.PoleUpright("no_such_joint").observe(_cartpole_env([0.0]))
    assert ttp.PoleUpright().verdict() == (0.0, False)  # nothing played, nothing passes


def test_velocity_tracking_error_in_the_plane():
    command = torch.tensor([[1.0, 0.0, 0.3], [0.0, 0.5, 0.0]])
    velocity = torch.tensor([[0.5, 0.0, 9.0], [0.0, 0.5, -3.0]])  # z is not judged
    env = SimpleNamespace(
        command_manager=SimpleNamespace(get_command=lambda name: {"twist": command}[name]),
        scene={"robot": SimpleNamespace(data=SimpleNamespace(root_link_lin_vel_b=velocity))},
    )
    judge = ttp.TracksVelocity()
    judge.observe(env)
    error, passed = judge.verdict()
    assert error == pytest.approx(0.25) and passed  # (0.5 + 0) / 2, at the limit
    judge.observe(
        SimpleNamespace(
            command_manager=env.command_manager,
            scene={"robot": SimpleNamespace(data=SimpleNamespace(root_link_lin_vel_b=torch.zeros(2, 3)))},
        )
    )
    assert judge.verdict() == (pytest.approx((0.5 + 0.0 + 1.0 + 0.5) / 4), False)


def _biped_env(command, lin_vel_w, ang_vel_z, yaw, terminated):
    half = torch.as_tensor(yaw) / 2
    quat = torch.stack([half.cos(), torch.zeros_like(half), torch.zeros_like(half), half.sin()], -1)
    ang_vel = torch.zeros(len(ang_vel_z), 3)
    ang_vel[:, 2] = torch.as_tensor(ang_vel_z)
    data = SimpleNamespace(
        root_link_quat_w=quat, root_link_lin_vel_w=torch.as_tensor(lin_vel_w), root_link_ang_vel_w=ang_vel
    )
    return SimpleNamespace(
        command_manager=SimpleNamespace(get_command=lambda name: {"twist": torch.as_tensor(command)}[name]),
        scene={"robot": SimpleNamespace(data=data)},
        termination_manager=SimpleNamespace(terminated=torch.as_tensor(terminated)),
        step_dt=0.02,
    )


def test_biped_criterion_judges_speed_in_the_heading_frame_yaw_rate_and_falls():
    # env 0 faces +y and walks +y at the commanded 0.5 m/s forward; env 1 stands, told to turn at 0.4 rad/s
    env = _biped_env(
        [[0.5, 0.0, 0.0], [0.0, 0.0, 0.4]],
        [[0.0, 0.5, 0.0], [0.0, 0.0, 0.0]],
        [0.0, 0.2],
        [math.pi / 2, 0.0],
        [False, False],
    )
    judge = ttp.BipedTracksVelocity()
    for _ in range(1000):  # 20 s
        judge.observe(env)
    speed, passed = judge.verdict()
    assert speed == pytest.approx(0.0, abs=1e-6) and passed  # yaw-rate error (0 + 0.2) / 2 = 0.1
    env.termination_manager.terminated = torch.tensor([True, False])  # one more step: a fall
    judge.observe(env)
    assert not judge.verdict()[1], "1 fall in 2 envs over 20 s is 50 %"
    assert ttp.criterion_for("Mjlab-Velocity-Flat-Unitree-G1") is ttp.BipedTracksVelocity
    assert ttp.BipedTracksVelocity.min_seconds == biped_tracks_velocity().min_seconds


def test_criteria_are_simlabs():
    pole = inspect.signature(pole_upright).parameters
    assert (pole["threshold"].default, pole["fraction"].default) == (ttp.POLE_ANGLE_RAD, ttp.POLE_UPRIGHT_FRACTION)
    assert inspect.signature(tracks_velocity).parameters["max_error"].default == ttp.VELOCITY_ERROR_M_S
    assert (BIPED_MAX_SPEED_ERROR, BIPED_MAX_YAW_RATE_ERROR, BIPED_MAX_FALL_RATE) == (
        ttp.BIPED_SPEED_ERROR_M_S,
        ttp.BIPED_YAW_RATE_ERROR_RAD_S,
        ttp.BIPED_FALL_RATE,
    )
    assert ttp.criterion_for("Mjlab-Cartpole-Balance") is ttp.PoleUpright
    assert ttp.criterion_for("Mjlab-Velocity-Flat-Unitree-Go1") is ttp.TracksVelocity
    with pytest.raises(ValueError, match="Cartpole and Velocity"):
        ttp.criterion_for("Mjlab-Lift-Cube-Yam")


def test_mjlab_cartpole_end_to_end_on_cpu(tmp_path):
    """Needs mjlab (and the MuJoCo it brings) importable; CI has neither."""
    pytest.importorskip("mjlab")
    argv = [sys.executable, str(SCRIPT), "Mjlab-Cartpole-Balance", "--device", "cpu", "--num-envs", "16"]
    argv += ["--max-iterations", "2", "--save-interval", "1", "--out", str(tmp_path)]
    done = subprocess.run(argv, capture_output=True, text=True, timeout=600, env=dict(os.environ, OUT=""))
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    row = json.loads((tmp_path / "Mjlab-Cartpole-Balance" / "result.json").read_text())
    assert [c["file"] for c in row["checkpoints"]] == ["model_0.pt", "model_1.pt"]
    assert all(0.0 <= c["score"] <= 1.0 for c in row["checkpoints"]) and row["startup_s"] > 0
