"""rsl_rl's student-teacher distillation through ``simlab train --agent rsl_rl_distillation_cfg_entry_point``
and Isaac Lab's rsl_rl scripts: the teacher is a PPO checkpoint (``--checkpoint``, the scripts'
``--load_run``), the student learns its actions on the states it visits and plays as any policy."""

from __future__ import annotations

import glob
import json
import os
import shutil

import pytest
import torch

from simlab.benchmarks.solve import CheckpointJudge
from simlab.cli.isaaclab_scripts import play_main, train_main
from simlab.cli.main import main
from simlab.pretrained import unpack_pretrained_checkpoint

TASK = "simlab/Cartpole-v0"
AGENT = "rsl_rl_distillation_cfg_entry_point"
ITERATIONS = 30


@pytest.fixture(scope="module")
def teacher(tmp_path_factory) -> str:
    """The shipped state cartpole policy as a PPO checkpoint: the teacher."""
    return unpack_pretrained_checkpoint(TASK, "rsl_rl", str(tmp_path_factory.mktemp("shipped")))


def _behaviour_losses(run_dir: str) -> list[float]:
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    events = EventAccumulator(run_dir)
    events.Reload()
    return [scalar.value for scalar in events.Scalars("Loss/behavior")]


def _judge(checkpoint: str) -> dict:
    judge = CheckpointJudge(TASK, "rsl_rl", "cpu", 16, 5.0, 42, agent=AGENT)
    try:
        judge(checkpoint, ITERATIONS - 1, {"rollout": 0.0, "update": 0.0})
    finally:
        judge.close()
    return judge.evaluations[-1]


def _distil(logs: str, load_run: str) -> str:
    """Isaac Lab's workflow: train.py --agent <distillation> --load_run <the teacher's run>; the student's run."""
    argv = ["--task", "Isaac-Cartpole-v0", "--agent", AGENT, "--load_run", load_run, "--headless"]
    argv += ["--device", "cpu", "--num_envs", "64", "--max_iterations", str(ITERATIONS), "--seed", "42"]
    assert train_main("rsl_rl", argv) == 0
    (run_dir,) = [d for d in glob.glob(os.path.join(logs, "rsl_rl", "cartpole", "*")) if not d.endswith(load_run)]
    return run_dir


def test_a_student_distilled_from_the_shipped_policy_imitates_it_and_balances_the_pole(tmp_path, monkeypatch, teacher):
    monkeypatch.chdir(tmp_path)  # Isaac Lab's scripts log to ./logs
    logs = str(tmp_path / "logs")
    shutil.copytree(os.path.dirname(teacher), os.path.join(logs, "rsl_rl", "cartpole", "2026-01-01_00-00-00_teacher"))
    run_dir = _distil(logs, "2026-01-01_00-00-00_teacher")
    last = os.path.join(run_dir, f"model_{ITERATIONS - 1}.pt")
    saved = torch.load(last, weights_only=True)
    shipped = torch.load(teacher, weights_only=True)["actor_state_dict"]
    assert set(saved["teacher_state_dict"]) == set(shipped)
    assert all(torch.equal(saved["teacher_state_dict"][k], shipped[k]) for k in shipped)  # the teacher, unchanged
    losses = _behaviour_losses(run_dir)
    assert len(losses) == ITERATIONS and losses[-1] < 0.1 * losses[0], losses
    played = _judge(last)
    assert played["passed"], played  # |pole angle| < 0.2 rad in >= 95 % of the steps: the student balances it

    # play.py with the same --agent plays the newest run of the experiment: the student
    assert play_main("rsl_rl", ["--task", "Isaac-Cartpole-v0", "--agent", AGENT, "--headless", "--device", "cpu"]
                     + ["--num_envs", "4", "--max_app_steps", "5"]) == 0  # fmt: skip
    assert os.path.isfile(os.path.join(run_dir, "exported", "policy.onnx"))


def test_a_student_of_a_teacher_that_does_nothing_does_not_balance_the_pole(tmp_path, monkeypatch, teacher):
    """The check above fails for a teacher whose weights are not the trained policy's: the student learns
    what it is taught, here a force of zero."""
    monkeypatch.chdir(tmp_path)
    logs = str(tmp_path / "logs")
    run = os.path.join(logs, "rsl_rl", "cartpole", "2026-01-01_00-00-00_teacher")
    os.makedirs(run)
    checkpoint = torch.load(teacher, weights_only=True)
    checkpoint["actor_state_dict"] = {k: torch.zeros_like(v) for k, v in checkpoint["actor_state_dict"].items()}
    torch.save(checkpoint, os.path.join(run, "model_149.pt"))
    run_dir = _distil(logs, "2026-01-01_00-00-00_teacher")
    assert not _judge(os.path.join(run_dir, f"model_{ITERATIONS - 1}.pt"))["passed"]


def _error(argv: list[str], capsys) -> str:
    assert main(argv) == 2
    lines = [line for line in capsys.readouterr().err.splitlines() if "error:" in line]
    assert len(lines) == 1
    return lines[0]


def test_distillation_errors_are_one_line(tmp_path, capsys, teacher):
    base = ["train", "--task", TASK, "--agent", AGENT, "--headless", "--device", "cpu", "--num_envs", "4"]
    base += ["--max_iterations", "1", "--log_root", str(tmp_path / "logs")]
    assert "needs the teacher's checkpoint: pass --checkpoint" in _error(base, capsys)
    with_teacher = [*base, "--checkpoint", teacher]
    line = _error([*with_teacher, "agent.obs_groups.teacher=[teacher]"], capsys)
    assert "teacher reads the observation group 'teacher', which simlab/Cartpole-v0 does not have" in line
    line = _error([*with_teacher, "agent.teacher.hidden_dims=[64,64]"], capsys)
    assert "does not fit agent.teacher (size mismatch for mlp.0.weight" in line
    play = ["play", "--task", TASK, "--agent", AGENT, "--checkpoint", teacher, "--headless", "--device", "cpu"]
    play += ["--num_envs", "2", "--steps", "1", "--log_root", str(tmp_path / "logs")]
    assert "holds a PPO policy (a teacher), not a distilled student" in _error(play, capsys)


def test_anymal_d_flat_distillation_is_registered_with_isaac_labs_settings():
    from simlab.tasks.utils import load_cfg_from_registry

    for task in ("simlab/Velocity-Flat-Anymal-D-v0", "simlab/Velocity-Flat-Anymal-D-Play-v0"):
        cfg = load_cfg_from_registry(task, AGENT)
        d = cfg.to_rsl_rl_dict(["policy"])
        assert d["obs_groups"] == {"student": ["policy"], "teacher": ["policy"]}
        assert (d["num_steps_per_env"], d["max_iterations"], d["save_interval"]) == (120, 300, 50)
        assert d["algorithm"] == {
            "class_name": "Distillation", "num_learning_epochs": 2, "learning_rate": 1.0e-3, "gradient_length": 15,
            "max_grad_norm": None, "optimizer": "adam", "loss_type": "mse",
        }  # fmt: skip
        # the teacher is the flat PPO actor's shape, so the teacher's checkpoint loads into it
        actor = load_cfg_from_registry(task, "rsl_rl_cfg_entry_point").to_rsl_rl_dict(["policy"])["actor"]
        assert {k: d["teacher"][k] for k in ("hidden_dims", "activation")} == {
            k: actor[k] for k in ("hidden_dims", "activation")
        }
        assert d["student"]["distribution_cfg"]["init_std"] == 0.1


@pytest.mark.slow  # 8 to 30 s on the 2-core machine: a training, three judged checkpoints, a CPU replay
def test_make_pretrained_distils_judges_and_ships_a_student_that_play_loads_with_its_agent(
    tmp_path, monkeypatch, teacher
):
    """scripts/make_pretrained.py --agent <distillation> --teacher <checkpoint>: simlab train distils, the
    checkpoints are judged by the task's criterion with that agent, the student alone is shipped, and
    play --use_pretrained_checkpoint loads it with the agent its record names."""
    from conftest import load_script

    import simlab.pretrained
    from simlab.cli.main import build_parser
    from simlab.cli.play import run_play
    from simlab.pretrained.weights import unpack_policy

    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    script = load_script(os.path.join(repo, "scripts", "make_pretrained.py"))
    out = tmp_path / "pretrained"
    argv = ["--tasks", TASK, "--agent", AGENT, "--teacher", teacher, "--device", "cpu", "--num_envs", "64"]
    argv += ["--max_iterations", str(ITERATIONS), "--eval_every", "10", "--eval_envs", "16", "--cpu_eval_envs", "16"]
    assert script.main([*argv, "--out", str(out)]) == 0
    shipped = out / "Cartpole-v0" / "rsl_rl"
    record = json.loads((shipped / "record.json").read_text())
    assert record["agent"] == AGENT and record["teacher"] == teacher
    assert f"--agent {AGENT} --checkpoint {teacher}" in record["train_command"]
    assert record["cpu_evaluation"]["passed"]
    name, checkpoint = unpack_policy(str(shipped / "policy.pt"))
    assert set(checkpoint) == {"student_state_dict", "iter", "infos"}  # no teacher, no optimizer

    monkeypatch.setattr(simlab.pretrained, "PRETRAINED_DIR", str(out))
    argv = ["play", "--task", TASK, "--use_pretrained_checkpoint", "--headless", "--device", "cpu"]
    argv += ["--num_envs", "2", "--steps", "5", "--log_root", str(tmp_path / "logs")]
    args = build_parser().parse_args(argv)
    result = run_play(args, [])
    assert args.agent == AGENT and result["steps"] == 5


def test_the_camera_cartpole_distils_the_state_policy_from_its_teacher_group(tmp_path, teacher):
    """The depth camera cartpole's teacher group is the state cartpole's policy observation, so the state
    policy loads as its teacher; one short iteration of its CNN student runs."""
    argv = ["train", "--task", "simlab/Cartpole-Depth-v0", "--agent", AGENT, "--checkpoint", teacher, "--headless"]
    argv += ["--device", "cpu", "--num_envs", "2", "--max_iterations", "1", "--log_root", str(tmp_path / "logs")]
    argv += ["agent.num_steps_per_env=4", "env.observations.policy.image.history_length=3"]
    argv += ["env.observations.policy.image.flatten_history_dim=False"]
    assert main(argv) == 0
    (checkpoint,) = glob.glob(str(tmp_path / "logs" / "rsl_rl" / "cartpole_camera_distillation" / "*" / "model_0.pt"))
    saved = torch.load(checkpoint, weights_only=True)
    shipped = torch.load(teacher, weights_only=True)["actor_state_dict"]
    assert all(torch.equal(saved["teacher_state_dict"][k], shipped[k]) for k in shipped)
    assert any(k.startswith("cnn") for k in saved["student_state_dict"])  # the student reads the images
    from simlab.utils.io import load_yaml

    info = load_yaml(os.path.join(os.path.dirname(checkpoint), "params", "run.yaml"))
    assert info["algorithm"] == "Distillation" and info["observations"]["teacher"] == 4 and info["teacher"] == teacher


def test_a_distillation_checkpoint_resumes_the_student(tmp_path, capsys, teacher):
    """--checkpoint of a distillation run (student, teacher and optimizer) resumes it where it stopped."""
    base = ["train", "--task", TASK, "--agent", AGENT, "--headless", "--device", "cpu", "--num_envs", "8"]
    base += ["--max_iterations", "2", "--log_root", str(tmp_path / "logs")]
    assert main([*base, "--checkpoint", teacher, "--run_name", "first"]) == 0
    (first,) = glob.glob(str(tmp_path / "logs" / "rsl_rl" / "cartpole" / "*_first" / "model_1.pt"))
    capsys.readouterr()
    assert main([*base, "--checkpoint", first, "--run_name", "second"]) == 0
    assert f"Resumed from {first} at iteration 1" in capsys.readouterr().out
    (last,) = glob.glob(str(tmp_path / "logs" / "rsl_rl" / "cartpole" / "*_second" / "model_2.pt"))
    resumed, started = torch.load(last, weights_only=True), torch.load(first, weights_only=True)
    assert resumed["iter"] == 2 and all(
        torch.equal(resumed["teacher_state_dict"][k], v) for k, v in started["teacher_state_dict"].items()
    )


def test_the_deprecated_student_teacher_config_converts_to_student_and_teacher_models():
    """Isaac Lab's rsl-rl < 4 form, ``policy = RslRlDistillationStudentTeacherCfg(...)``: the same runner dict
    as the student / teacher form (the teacher with the Gaussian output a PPO actor's checkpoint has)."""
    from simlab.rl.rsl_rl import RslRlDistillationRunnerCfg, RslRlDistillationStudentTeacherCfg
    from simlab.tasks.utils import load_cfg_from_registry

    new = load_cfg_from_registry("simlab/Velocity-Flat-Anymal-D-v0", AGENT)
    old = RslRlDistillationRunnerCfg(
        num_steps_per_env=120,
        max_iterations=300,
        save_interval=50,
        experiment_name="anymal_d_flat",
        obs_groups={"student": ["policy"], "teacher": ["policy"]},
        policy=RslRlDistillationStudentTeacherCfg(
            init_noise_std=0.1,
            student_hidden_dims=[128, 128, 128],
            teacher_hidden_dims=[128, 128, 128],
            activation="elu",
        ),
        algorithm=new.algorithm,
    )
    assert old.to_rsl_rl_dict(["policy"]) == new.to_rsl_rl_dict(["policy"])
    with pytest.raises(ValueError, match="not both"):
        old.replace(student=new.student).to_rsl_rl_dict(["policy"])
