"""scripts/make_pretrained.py: train, judge by the task's criterion, ship where --use_pretrained_checkpoint finds it.

The cartpole with tiny settings on the CPU: a policy of two iterations does not balance the pole,
so the shipping path runs with a mean-reward threshold any policy meets, and the criterion's own
verdict is checked with the real one.
"""

from __future__ import annotations

import json
import os
import shutil
import zipfile

import numpy as np
import onnxruntime
import pytest
import torch
from conftest import load_script

import simlab.pretrained
from simlab.cli.main import build_parser
from simlab.cli.play import run_play
from simlab.pretrained.weights import PLAY_KEYS, pack_policy, unpack_policy
from simlab.tasks.utils.criteria import criterion_for

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TASK = "simlab/Cartpole-Direct-v0"
TINY = ["--device", "cpu", "--num_envs", "8", "--max_iterations", "2", "--eval_every", "1"]
TINY += ["--eval_envs", "4", "--cpu_eval_envs", "4", "--eval_seconds", "0.5", "--seed", "3"]


def _script():
    return load_script(os.path.join(REPO, "scripts", "make_pretrained.py"))


def test_make_pretrained_ships_a_policy_that_play_finds(tmp_path, monkeypatch):
    out = tmp_path / "pretrained"
    script = _script()
    assert script.main(["--tasks", TASK, *TINY, "--reward_threshold=-1e9", "--out", str(out)]) == 0

    shipped = out / "Cartpole-Direct-v0" / "rsl_rl"
    record = json.loads((shipped / "record.json").read_text())
    assert record["task"] == TASK and record["seed"] == 3 and record["num_envs"] == 8
    assert 1 <= record["iterations"] <= 2
    assert record["criterion"] == "mean reward per env-step >= -1e+09"
    assert record["cpu_evaluation"]["passed"] and record["cpu_evaluation"]["envs"] == 4
    # trained by simlab train itself: the task's registered agent config, this script's settings
    assert record["train_command"].startswith("simlab train --task simlab/Cartpole-Direct-v0 --library rsl_rl")
    assert "agent.save_interval=1" in record["train_command"]
    assert record["made_by"].startswith("python scripts/make_pretrained.py --tasks simlab/Cartpole-Direct-v0")
    # one file of weights, what play loads (no critic, no optimizer), read with weights_only=True
    # not the resolved env config (rebuilt from the task and the command); a direct task lists no terms
    assert sorted(record["files_bytes"]) == ["params/agent.yaml", "params/command.txt", "params/run.yaml", "policy.pt"]
    assert not (shipped / "params" / "env.yaml").exists() and "observations" not in record
    assert record["files_bytes"]["policy.pt"] == os.path.getsize(shipped / "policy.pt")
    assert record["weights"] == "int8_rows"  # the smallest form: its replay met the criterion
    assert {entry.compress_type for entry in zipfile.ZipFile(shipped / "policy.pt").infolist()} == {
        zipfile.ZIP_DEFLATED
    }
    name, checkpoint = unpack_policy(str(shipped / "policy.pt"))
    assert name == record["checkpoint"] and set(checkpoint) == set(PLAY_KEYS["rsl_rl"])

    # simlab play --use_pretrained_checkpoint finds it (the package's folder pointed at the output)
    monkeypatch.setattr(simlab.pretrained, "PRETRAINED_DIR", str(out))
    argv = ["play", "--task", TASK, "--use_pretrained_checkpoint", "--headless", "--device", "cpu"]
    argv += ["--num_envs", "2", "--steps", "5", "--log_root", str(tmp_path / "logs")]
    result = run_play(build_parser().parse_args(argv), [])
    played = os.path.dirname(result["checkpoint"])
    assert played.startswith(str(tmp_path / "logs" / "pretrained"))
    # with the record's envs, seconds and seed, play runs the episodes the CPU replay judged: the same score
    replay = record["cpu_evaluation"]
    argv = ["play", "--task", TASK, "--use_pretrained_checkpoint", "--headless", "--device", "cpu"]
    argv += ["--num_envs", str(replay["envs"]), "--seconds", str(replay["seconds"]), "--seed", str(replay["seed"])]
    on_step, state = criterion_for(TASK, -1e9).make_hook()
    result = run_play(build_parser().parse_args([*argv, "--log_root", str(tmp_path / "logs")]), [], on_step=on_step)
    assert criterion_for(TASK, -1e9).judge(result, state)[0] == replay["score"]
    # play exported the shipped policy into the user's folder: ONNX and TorchScript act alike
    observations = torch.randn(16, 4)
    session = onnxruntime.InferenceSession(os.path.join(played, "exported", "policy.onnx"))
    (onnx_actions,) = session.run(None, {session.get_inputs()[0].name: observations.numpy()})
    torch_actions = torch.jit.load(os.path.join(played, "exported", "policy.pt"))(observations)
    np.testing.assert_allclose(onnx_actions, torch_actions.detach().numpy(), atol=1e-5)


def test_make_pretrained_ships_nothing_that_misses_the_criterion(tmp_path, capsys):
    out = tmp_path / "pretrained"
    assert _script().main(["--tasks", TASK, *TINY, "--out", str(out)]) == 1
    assert not out.exists()
    printed = capsys.readouterr().out
    assert f"SKIPPED {TASK}: not solved in 2 iterations (|pole angle| < 0.2 rad" in printed
    assert f"{TASK}: NOT shipped" in printed


def test_make_pretrained_refuses_a_task_it_cannot_judge_or_train_before_training(tmp_path):
    script = _script()
    with pytest.raises(ValueError, match="simlab/Humanoid-AMP-Walk-Direct-v0 has no rsl_rl config"):
        script.main(["--tasks", TASK, "simlab/Humanoid-AMP-Walk-Direct-v0", "--out", str(tmp_path)])
    with pytest.raises(SystemExit):  # --eval_every is rsl_rl's save_interval; skrl's goes in --overrides
        script.main(["--tasks", TASK, "--library", "skrl", "--eval_every", "5", "--out", str(tmp_path)])
    with pytest.raises(ValueError, match="Unknown task simlab/Nope-v0"):
        script.main(["--tasks", "simlab/Nope-v0", "--out", str(tmp_path)])
    with pytest.raises(SystemExit):  # a bc policy is fitted to demonstrations: only --checkpoint ships one
        script.main(["--tasks", "simlab/Stack-Cube-Franka-IK-Abs-v0", "--library", "bc", "--out", str(tmp_path)])
    assert not os.listdir(tmp_path)


def test_a_batch_skips_each_task_over_its_time_budget_with_a_line_and_goes_on(tmp_path, capsys):
    out = tmp_path / "pretrained"
    tasks = ["--tasks", TASK, "simlab/Cartpole-v0"]
    assert _script().main([*tasks, *TINY, "--time_budget", "0.5", "--out", str(out)]) == 1
    printed = capsys.readouterr().out
    for task in (TASK, "simlab/Cartpole-v0"):  # the second trained after the first was skipped
        assert (
            f"SKIPPED {task}: not solved within the time budget of 0.5 s (no checkpoint written); nothing shipped"
            in printed
        )
    assert not out.exists()


def test_the_task_list_names_every_tasks_criterion():
    rows = {row["task"]: row for row in _script().task_table()}
    assert len(rows) >= 28 and not any("-Play-" in task for task in rows)  # the ids less the Play variants
    assert rows["simlab/Cartpole-Direct-v0"]["shipped"] == ["rsl_rl"]
    assert rows["simlab/Reach-Franka-OSC-v0"]["criterion"].startswith("at the end of each command window")
    assert rows["simlab/Humanoid-AMP-Run-Direct-v0"]["criterion"].startswith("forward speed >= 50% of the clip's")
    assert rows["simlab/Humanoid-AMP-Run-Direct-v0"]["shipped"] == ["skrl"]
    assert (
        not rows["simlab/Humanoid-AMP-Walk-Direct-v0"]["rsl_rl"]
        and rows["simlab/Open-Drawer-Franka-IK-Rel-v0"]["rsl_rl"]
    )
    assert not any(row["criterion"].startswith("none") for row in rows.values())


def test_a_policy_trained_elsewhere_is_judged_on_the_cpu_and_shipped(tmp_path, capsys):
    from simlab.cli.main import main as simlab_main

    logs = tmp_path / "logs"
    train = ["train", "--task", TASK, "--headless", "--device", "cpu", "--num_envs", "8", "--max_iterations", "1"]
    assert simlab_main([*train, "--seed", "3", "--log_root", str(logs)]) == 0
    checkpoint = tmp_path / "model_final.pt"  # a name of its own, as a script of the user's saves
    shutil.copy2(max(logs.glob("rsl_rl/*/*/model_*.pt"), key=os.path.getmtime), checkpoint)
    script = _script()
    adopt = ["--tasks", TASK, "--checkpoint", str(checkpoint), "--trained_by", "a one-iteration test run"]
    adopt += ["--cpu_eval_envs", "4", "--eval_seconds", "0.5"]

    out = tmp_path / "pretrained"
    assert script.main([*adopt, "--reward_threshold=-1e9", "--out", str(out)]) == 0
    shipped = out / "Cartpole-Direct-v0" / "rsl_rl"
    record = json.loads((shipped / "record.json").read_text())
    assert record["trained_by"] == "a one-iteration test run" and record["cpu_evaluation"]["passed"]
    # a name play's checkpoint search finds; one iteration: rsl_rl's iteration 0
    assert record["checkpoint"] == "model_0.pt" and record["iterations"] == 1
    assert "simlab/Cartpole-Direct-v0" in (shipped / "params" / "run.yaml").read_text()
    name, checkpoint = unpack_policy(str(shipped / "policy.pt"))
    assert name == record["checkpoint"] and set(checkpoint) == set(PLAY_KEYS["rsl_rl"])
    assert not (shipped / "exported").exists()

    # judged by the task's own criterion, a one-iteration policy is not shipped
    refused = tmp_path / "refused"
    assert script.main([*adopt, "--out", str(refused)]) == 1
    assert "failed on the CPU" in capsys.readouterr().out and not refused.exists()
    with pytest.raises(SystemExit):  # one policy, one task
        script.main([*adopt, "--tasks", TASK, "simlab/Cartpole-v0"])


def test_an_skrl_policy_trained_elsewhere_is_shipped_in_skrls_layout(tmp_path):
    from simlab.cli.main import main as simlab_main

    logs = tmp_path / "logs"
    train = ["train", "--task", TASK, "--library", "skrl", "--headless", "--device", "cpu", "--num_envs", "8"]
    assert simlab_main([*train, "--max_iterations", "1", "--seed", "3", "--log_root", str(logs)]) == 0
    checkpoint = max(logs.glob("skrl/*/*/checkpoints/agent_*.pt"), key=os.path.getmtime)
    script = _script()
    adopt = ["--tasks", TASK, "--library", "skrl", "--checkpoint", str(checkpoint), "--trained_by", "a test run"]
    adopt += ["--cpu_eval_envs", "4", "--eval_seconds", "0.5", "--reward_threshold=-1e9"]
    out = tmp_path / "pretrained"
    assert script.main([*adopt, "--out", str(out)]) == 0

    shipped = out / "Cartpole-Direct-v0" / "skrl"
    record = json.loads((shipped / "record.json").read_text())
    assert record["library"] == "skrl" and record["algorithm"] == "PPO" and record["cpu_evaluation"]["passed"]
    assert record["iterations"] == 1  # agent_<rollouts>.pt: written after one rollout and its update
    # skrl's layout: play writes the checkpoint (policy and its normalizer only) into checkpoints/
    name, checkpoint = unpack_policy(str(shipped / "policy.pt"))
    assert name == f"checkpoints/{record['checkpoint']}" and set(checkpoint) == set(PLAY_KEYS["skrl"])


def test_a_policy_trained_with_env_overrides_is_shipped_and_played_with_them(tmp_path, monkeypatch):
    # two stacked depth images: the override changes the observation, so play must apply it too
    task = "simlab/Cartpole-Depth-Camera-Direct-v0"
    script = _script()
    tiny = ["--device", "cpu", "--num_envs", "4", "--max_iterations", "1", "--eval_every", "1", "--seed", "3"]
    tiny += ["--eval_envs", "2", "--cpu_eval_envs", "2", "--eval_seconds", "0.2", "--reward_threshold=-1e9"]
    out = tmp_path / "pretrained"
    assert script.main(["--tasks", task, *tiny, "--overrides", "env.frame_stack=2", "--out", str(out)]) == 0
    record = json.loads((out / "Cartpole-Depth-Camera-Direct-v0" / "rsl_rl" / "record.json").read_text())
    assert record["env_overrides"] == ["env.frame_stack=2"]
    assert record["train_command"].endswith(" env.frame_stack=2")  # a Hydra override of simlab train

    monkeypatch.setattr(simlab.pretrained, "PRETRAINED_DIR", str(out))
    argv = ["play", "--task", task, "--use_pretrained_checkpoint", "--headless", "--device", "cpu"]
    argv += ["--num_envs", "2", "--steps", "2", "--log_root", str(tmp_path / "logs")]
    shapes = []
    run_play(build_parser().parse_args(argv), [], on_step=lambda env, obs, actions: shapes.append(obs["policy"].shape))
    assert shapes == [(2, 100, 100, 2)] * 2  # H, W, one depth channel per stacked image

    with pytest.raises(SystemExit):  # an override names the env or the agent config
        script.main(["--tasks", task, *tiny, "--overrides", "frame_stack=2"])


def test_a_failing_cpu_replay_names_the_passing_checkpoint_and_how_to_ship_it(tmp_path, capsys, monkeypatch):
    from simlab.utils.gl_backend import GLBackendError

    script = _script()

    def no_opengl(*args, **kwargs):  # a GPU host without OpenGL replaying a camera policy
        raise GLBackendError("No OpenGL backend renders offscreen here")

    monkeypatch.setattr(script, "evaluate_on_cpu", no_opengl)
    out = tmp_path / "pretrained"
    argv = ["--tasks", TASK, *TINY, "--reward_threshold=-1e9", "--out", str(out), "--log_root", str(tmp_path / "logs")]
    assert script.main(argv) == 1
    printed = capsys.readouterr().out
    assert f"SKIPPED {TASK}: model_" in printed and "passed on cpu" in printed and "No OpenGL backend" in printed
    checkpoint = printed.split("--checkpoint ")[1].split()[0]
    assert os.path.isfile(checkpoint) and not out.exists()  # kept for --checkpoint, nothing shipped


def test_a_checkpoint_whose_cpu_replay_misses_is_passed_over_for_a_later_one(tmp_path, capsys, monkeypatch):
    script = _script()
    replayed = []

    def replay(task, staged, iteration, args):  # the first checkpoint sits at the criterion's edge on the CPU
        replayed.append(iteration)
        passed = iteration > 0
        return {"device": "cpu", "envs": 4, "seconds": 0.5, "seed": 3, "score": float(passed), "passed": passed}

    monkeypatch.setattr(script, "evaluate_on_cpu", replay)
    out = tmp_path / "pretrained"
    argv = ["--tasks", TASK, *TINY, "--reward_threshold=-1e9", "--out", str(out), "--log_root", str(tmp_path / "logs")]
    assert script.main(argv) == 0
    assert replayed[0] == 0 and replayed[-1] > 0  # both stored forms of model_0 missed, then a later one passed
    assert "model_0.pt passed on cpu" in capsys.readouterr().out
    record = json.loads((out / "Cartpole-Direct-v0" / "rsl_rl" / "record.json").read_text())
    assert record["checkpoint"] != "model_0.pt" and record["cpu_evaluation"]["passed"]


def test_a_training_stopped_by_the_budget_saves_where_it_is_and_says_how_to_go_on(tmp_path):
    import subprocess
    import time

    script = _script()
    log_root = tmp_path / "logs"
    args = script.parse_args(["--tasks", TASK, "--device", "cpu", "--num_envs", "8", "--max_iterations", "100000"])
    command = script.train_command(TASK, args, str(log_root))
    started = time.time()
    child = subprocess.Popen(command, cwd=REPO, start_new_session=True, stdout=subprocess.PIPE, text=True)
    deadline = time.time() + 300
    while not list(log_root.glob("rsl_rl/*/*_make_pretrained/model_0.pt")):  # rsl_rl saves iteration 0: training runs
        assert child.poll() is None and time.time() < deadline, "the training ended before its first checkpoint"
        time.sleep(0.2)
    saved = script.stop_and_save(child, str(log_root), started)
    assert child.returncode == 143  # SIGTERM, handled as Ctrl+C: the training saved the iteration it was at
    assert f"Interrupted: saved {saved}" in child.stdout.read() and os.path.isfile(saved)

    args = script.parse_args(["--tasks", TASK, "--time_budget", "9", "--log_root", str(log_root)])
    args.overrides = ["env.episode_length_s=4"]  # trained with it: going on and shipping keep it
    text = script.over_budget_text(TASK, args, saved)
    assert f"--tasks {TASK} --resume {saved} --device cpu --time_budget 9 --log_root {log_root} --overrides" in text
    assert "--overrides env.episode_length_s=4`" in text
    assert f"--checkpoint {saved} --trained_by ... --overrides env.episode_length_s=4`" in text
    scratch = script.parse_args(["--tasks", TASK, "--time_budget", "9"])
    assert "give --log_root to keep it" in script.over_budget_text(TASK, scratch, saved)
    assert script.over_budget_text(TASK, scratch, None).endswith("(no checkpoint written)")


def test_the_command_that_trains_on_keeps_the_runs_envs_budget_judging_and_folder():
    """A training chunked over calls (the GPU's 10-minute limit) goes on with the settings it had: the
    suggested command once left out --num_envs, --time_budget and --log_root (a resumed run then took the
    task's envs, trained without a budget and kept its checkpoints in a temporary folder)."""
    script = _script()
    argv = ["--tasks", TASK, "--device", "cuda:0", "--num_envs", "8192", "--time_budget", "420"]
    argv += ["--eval_every", "150", "--eval_envs", "128", "--log_root", "logs/hands"]
    text = script.over_budget_text(TASK, script.parse_args(argv), "logs/hands/model_300.pt")
    train_on = text.split("train on with `")[1].split("`")[0]
    assert train_on == (
        f"python scripts/make_pretrained.py --tasks {TASK} --resume logs/hands/model_300.pt --device cuda:0"
        " --num_envs 8192 --time_budget 420 --eval_every 150 --eval_envs 128 --log_root logs/hands"
    )
    ship = text.split("ship it as it is with `")[1].split("`")[0]
    assert "--num_envs" not in ship and "--time_budget" not in ship  # shipping judges on the CPU, no training


def test_a_training_someone_else_stops_is_skipped_naming_the_checkpoint_it_saved(tmp_path, capsys):
    import subprocess
    import threading
    import time

    log_root = tmp_path / "logs"

    def stop_after_the_first_checkpoint() -> None:
        deadline = time.time() + 300
        while not list(log_root.glob("rsl_rl/*/*_make_pretrained/model_0.pt")) and time.time() < deadline:
            time.sleep(0.2)
        time.sleep(1.0)
        subprocess.run(["pkill", "-TERM", "-f", f"simlab train .*{log_root}"], check=True)

    threading.Thread(target=stop_after_the_first_checkpoint, daemon=True).start()
    argv = ["--tasks", TASK, "--device", "cpu", "--num_envs", "8", "--max_iterations", "100000"]
    argv += ["--eval_every", "100000", "--eval_envs", "4", "--eval_seconds", "0.5"]
    assert _script().main([*argv, "--log_root", str(log_root), "--out", str(tmp_path / "out")]) == 1
    out = capsys.readouterr().out
    (saved,) = [p for p in log_root.glob("rsl_rl/*/*_make_pretrained/model_*.pt") if p.name != "model_0.pt"]
    assert f"training was stopped by a SIGTERM; its last checkpoint is {saved}: train on with" in out
    assert f"--resume {saved} --device cpu" in out


def test_resume_trains_on_from_a_checkpoint_and_records_it(tmp_path):
    script = _script()
    logs = tmp_path / "logs"
    first = ["--tasks", TASK, *TINY, "--out", str(tmp_path / "none"), "--log_root", str(logs)]
    assert script.main(first) == 1  # two iterations do not balance the pole: its checkpoints stay in logs
    (checkpoint,) = logs.glob("rsl_rl/*/*_make_pretrained/model_1.pt")
    out = tmp_path / "pretrained"
    argv = ["--tasks", TASK, *TINY, "--reward_threshold=-1e9", "--out", str(out), "--resume", str(checkpoint)]
    assert script.main(argv) == 0
    record = json.loads((out / "Cartpole-Direct-v0" / "rsl_rl" / "record.json").read_text())
    assert record["resumed_from"] == str(checkpoint) and f"--checkpoint {checkpoint}" in record["train_command"]
    # and how the resumed checkpoint itself was trained (its run's command, not in the new run's)
    first_command = (checkpoint.parent / "params" / "command.txt").read_text().strip()
    assert record["resumed_from_command"] == first_command and "--checkpoint" not in first_command
    # trained on: counted on from the resumed iteration (rsl_rl numbers the first iteration after a resume
    # as the checkpoint's own), with weights that moved away from the checkpoint's
    _, shipped = unpack_policy(str(out / "Cartpole-Direct-v0" / "rsl_rl" / "policy.pt"))
    resumed = torch.load(checkpoint, weights_only=False)
    assert shipped["iter"] >= resumed["iter"] == 1
    torch.save(pack_policy(resumed, "rsl_rl", "model_1.pt"), tmp_path / "resumed.pt")  # stored alike
    _, resumed = unpack_policy(str(tmp_path / "resumed.pt"))
    moved = [not torch.equal(shipped["actor_state_dict"][k], v) for k, v in resumed["actor_state_dict"].items()]
    assert any(moved)
    with pytest.raises(SystemExit):  # a missing checkpoint is a usage error before any training
        script.parse_args(["--tasks", TASK, "--resume", str(tmp_path / "missing.pt")])


def test_an_adopted_checkpoint_gets_a_name_that_play_finds():
    make_pretrained = _script()
    agent_cfg = {"agent": {"rollouts": 16}}
    # a copy named by its user ends in the library's pattern but does not start with it
    assert make_pretrained.checkpoint_name("/x/dance_agent_27200.pt", "skrl", 1699, agent_cfg) == "agent_27200.pt"
    assert make_pretrained.checkpoint_name("/x/agent_800.pt", "skrl", 49, agent_cfg) == "agent_800.pt"
    assert make_pretrained.checkpoint_name("/x/best_model_9.pt", "rsl_rl", 9, agent_cfg) == "model_9.pt"


def test_skrl_checkpoints_count_iterations_as_rsl_rl_does():
    """skrl writes agent_<T>.pt after T steps, T // rollouts updates: iteration T // rollouts - 1 counted
    from 0 as rsl_rl's model_<iter>.pt, so record.json's iterations (iteration + 1) is the updates done."""
    make_pretrained = _script()
    agent_cfg = {"agent": {"rollouts": 16}}
    assert make_pretrained.checkpoint_iteration("/x/agent_480.pt", "skrl", agent_cfg) == 29  # 30 updates
    assert make_pretrained.checkpoint_iteration("/x/agent_16.pt", "skrl", agent_cfg) == 0
    assert make_pretrained.checkpoint_name("/x/final.pt", "skrl", 29, agent_cfg) == "agent_480.pt"


def test_a_policy_whose_int8_replay_misses_the_criterion_is_stored_as_float16(tmp_path, monkeypatch):
    from simlab.cli.main import main as simlab_main

    logs = tmp_path / "logs"
    train = ["train", "--task", TASK, "--headless", "--device", "cpu", "--num_envs", "8", "--max_iterations", "1"]
    assert simlab_main([*train, "--seed", "3", "--log_root", str(logs)]) == 0
    checkpoint = max(logs.glob("rsl_rl/*/*/model_*.pt"), key=os.path.getmtime)
    script = _script()
    tried = []

    def replay(task, staged, iteration, args):  # a task whose tolerance int8 rows miss, float16 meets
        matrices = torch.load(os.path.join(os.path.dirname(staged), "policy.pt"), weights_only=True)["matrices"]
        tried.append(matrices)
        passed = matrices == "float16"
        return {"device": "cpu", "envs": 4, "seconds": 0.5, "seed": 42, "score": float(passed), "passed": passed}

    monkeypatch.setattr(script, "evaluate_on_cpu", replay)
    out = tmp_path / "pretrained"
    adopt = ["--tasks", TASK, "--checkpoint", str(checkpoint), "--trained_by", "a test run", "--out", str(out)]
    assert script.main(adopt) == 0 and tried == ["int8_rows", "float16"]
    record = json.loads((out / "Cartpole-Direct-v0" / "rsl_rl" / "record.json").read_text())
    assert record["weights"] == "float16" and record["cpu_evaluation"]["score"] == 1.0
    _, stored = unpack_policy(str(out / "Cartpole-Direct-v0" / "rsl_rl" / "policy.pt"))
    original = torch.load(checkpoint, weights_only=True)["actor_state_dict"]
    for key, value in stored["actor_state_dict"].items():
        assert value.dtype == torch.float32
        torch.testing.assert_close(value, original[key], rtol=1e-3, atol=1e-4)  # float16's precision


def test_a_batch_judges_only_its_own_checkpoints_in_a_shared_log_root(tmp_path):
    """Two make_pretrained processes training on one GPU into one log root: each finds only the
    checkpoints of its own runs (on an H200, a Spot batch judged a Go1 batch's checkpoints)."""
    import time

    script = _script()
    started = time.time() - 1
    ours = tmp_path / "rsl_rl" / "spot_flat" / f"2026-12-06_20-51-31_{script.RUN_NAME}"
    theirs = tmp_path / "rsl_rl" / "unitree_go1_flat" / "2026-12-06_20-51-30_999999_make_pretrained"
    for run in (ours, theirs):
        run.mkdir(parents=True)
        (run / "model_25.pt").write_bytes(b"")
    assert script.run_checkpoints(str(tmp_path), started) == [str(ours / "model_25.pt")]


@pytest.mark.parametrize("saved", [[1, 2], {"iter": 3}])
def test_a_file_that_is_not_a_bc_policy_gets_a_one_line_error(tmp_path, saved):
    """--library bc reads the epochs of the fit: a list (AttributeError before) or another library's dict
    is refused in one line naming the file."""
    from simlab.utils.errors import CheckpointError

    path = tmp_path / "policy.pt"
    torch.save(saved, path)
    with pytest.raises(CheckpointError, match="is not a BC policy") as caught:
        _script().checkpoint_iteration(str(path), "bc", {})
    assert "\n" not in str(caught.value)


def test_a_deflated_policy_file_loads_as_the_stored_one_and_is_smaller(tmp_path):
    """The shipped form of policies: torch.save's archive with its entries deflated; it reads back
    through the loader to the same weights as torch.save's plain archive."""
    from simlab.pretrained.weights import save_policy

    shipped = os.path.join(REPO, "simlab", "pretrained", "Humanoid-AMP-Walk-Direct-v0", "skrl", "policy.pt")
    plain, deflated = str(tmp_path / "plain.pt"), str(tmp_path / "policy.pt")
    torch.save(torch.load(shipped, weights_only=True), plain)
    save_policy(torch.load(shipped, weights_only=True), deflated)
    assert {entry.compress_type for entry in zipfile.ZipFile(deflated).infolist()} == {zipfile.ZIP_DEFLATED}
    assert os.path.getsize(deflated) < 0.95 * os.path.getsize(plain)  # int8 rows: 621,673 -> 581,393 bytes
    (name, checkpoint), (plain_name, plain_checkpoint) = unpack_policy(deflated), unpack_policy(plain)
    assert name == plain_name
    torch.testing.assert_close(checkpoint, plain_checkpoint, rtol=0, atol=0)


def test_a_checkpoint_whose_play_raises_skips_its_task_with_a_line_and_the_batch_goes_on(tmp_path, capsys, monkeypatch):
    """A policy that drove the env to NaN while it was judged once ended the whole batch with a traceback."""
    from simlab.benchmarks.solve import CheckpointJudge

    played = CheckpointJudge.__call__

    def nan_on_the_first_task(judge, path, iteration, seconds):
        if judge.task == TASK:
            raise ValueError("Observations or rewards contained NaN or inf after a step: obs['policy']\nmore")
        return played(judge, path, iteration, seconds)

    monkeypatch.setattr(CheckpointJudge, "__call__", nan_on_the_first_task)
    out, log_root = tmp_path / "pretrained", tmp_path / "logs"
    argv = ["--tasks", TASK, "simlab/Cartpole-v0", *TINY, "--reward_threshold=-1e9"]
    assert _script().main([*argv, "--out", str(out), "--log_root", str(log_root)]) == 1
    printed = capsys.readouterr().out
    (skipped,) = [line for line in printed.splitlines() if "SKIPPED" in line]
    (run,) = log_root.glob("rsl_rl/cartpole_direct/*_make_pretrained")
    assert f"SKIPPED {TASK}: judging {run}/model_0.pt failed: ValueError: Observations or rewards" in skipped
    assert "more" not in skipped and f"--resume {run}/model_1.pt --device cpu" in skipped
    assert skipped.endswith("; nothing shipped")
    # the batch went on: the second task trained, was judged and shipped
    assert (out / "Cartpole-v0" / "rsl_rl" / "record.json").is_file() and not (out / "Cartpole-Direct-v0").exists()
    assert f"{TASK}: NOT shipped; simlab/Cartpole-v0: shipped" in printed


def test_an_rl_games_training_is_judged_shipped_and_played(tmp_path, monkeypatch):
    """rl_games trains the in-hand tasks in Isaac Lab's validated runs: make_pretrained trains with it,
    judges its checkpoints (``--eval_every`` is rl_games' save_frequency), ships the played part of
    one and play finds it. Before, ``--library rl_games`` was refused (a usage error)."""
    out = tmp_path / "pretrained"
    argv = ["--tasks", TASK, *TINY, "--library", "rl_games", "--reward_threshold=-1e9", "--out", str(out)]
    assert _script().main([*argv, "--log_root", str(tmp_path / "runs")]) == 0
    # a checkpoint every epoch: one per epoch and the last one
    assert len(list((tmp_path / "runs").glob("rl_games/*/*_make_pretrained/nn/*.pth"))) >= 2

    shipped = out / "Cartpole-Direct-v0" / "rl_games"
    record = json.loads((shipped / "record.json").read_text())
    assert record["library"] == "rl_games" and record["cpu_evaluation"]["passed"]
    assert "agent.params.config.save_frequency=1" in record["train_command"]
    assert 1 <= record["iterations"] <= 2  # rl_games' epochs, counted as rsl_rl's iterations
    name, checkpoint = unpack_policy(str(shipped / "policy.pt"))
    assert name.startswith("nn/") and name.endswith(".pth") and set(checkpoint) == set(PLAY_KEYS["rl_games"])
    assert "optimizer" not in checkpoint  # what play loads only

    monkeypatch.setattr(simlab.pretrained, "PRETRAINED_DIR", str(out))
    argv = ["play", "--task", TASK, "--use_pretrained_checkpoint", "--library", "rl_games", "--headless"]
    argv += ["--device", "cpu", "--num_envs", "2", "--steps", "5", "--log_root", str(tmp_path / "logs")]
    result = run_play(build_parser().parse_args(argv), [])
    assert result["checkpoint"].endswith(name.split("/")[-1])


def test_rl_games_checkpoints_count_iterations_as_rsl_rl_does(tmp_path):
    """rl_games stores the epochs done (1 after the first update): iteration epoch - 1, as rsl_rl's model_<iter>.pt."""
    make_pretrained = _script()
    path = tmp_path / "last_cartpole_ep_30_rew_5.0.pth"
    torch.save({"model": {}, "epoch": 30, "frame": 1}, path)
    assert make_pretrained.checkpoint_iteration(str(path), "rl_games", {}) == 29
    assert make_pretrained.checkpoint_name(str(path), "rl_games", 29, {}) == path.name
    assert make_pretrained.checkpoint_name("/x/policy.pt", "rl_games", 29, {}) == "last_ep_30.pth"


def test_restore_stores_a_shipped_float16_policy_again_as_int8_rows_and_play_loads_it(tmp_path, monkeypatch):
    """--restore: a policy shipped as float16 (before rsl_rl's (1, N) normalizer rows stayed float32) is
    stored again from its own policy.pt in the smallest form whose replay, as its record ran it, passes."""
    from simlab.pretrained.weights import save_policy

    out = tmp_path / "pretrained"
    script = _script()
    assert script.main(["--tasks", TASK, *TINY, "--reward_threshold=-1e9", "--out", str(out)]) == 0
    shipped = out / "Cartpole-Direct-v0" / "rsl_rl"
    name, checkpoint = unpack_policy(str(shipped / "policy.pt"))
    save_policy(pack_policy(checkpoint, "rsl_rl", name, "float16"), str(shipped / "policy.pt"))
    record = json.loads((shipped / "record.json").read_text())
    (shipped / "record.json").write_text(json.dumps({**record, "weights": "float16"}, indent=2) + "\n")
    float16_bytes = os.path.getsize(shipped / "policy.pt")

    assert script.main(["--restore", "--tasks", TASK, "--out", str(out)]) == 0
    restored = json.loads((shipped / "record.json").read_text())
    assert restored["weights"] == "int8_rows" and restored["cpu_evaluation"]["passed"]
    assert restored["files_bytes"]["policy.pt"] == os.path.getsize(shipped / "policy.pt") < float16_bytes
    assert restored["train_command"] == record["train_command"]  # how it was trained stays
    assert "from its shipped float16 weights" in restored["weights_note"]
    replay = restored["cpu_evaluation"]  # the record's play: its envs, seconds and seed
    assert (replay["envs"], replay["seconds"], replay["seed"]) == (4, 0.5, 3)
    stored = torch.load(shipped / "policy.pt", weights_only=True)["state"]["actor_state_dict"]
    _, back = unpack_policy(str(shipped / "policy.pt"))
    for key, value in checkpoint["actor_state_dict"].items():
        if sum(size > 1 for size in value.shape) >= 2:  # int8 rows of the float16 weights, within half a step
            assert stored[key]["__packed__"] == "int8_rows"
            step = value.abs().amax(dim=1, keepdim=True) / 127
            assert bool(((back["actor_state_dict"][key] - value).abs() <= step / 2 + 1e-3 * value.abs()).all())
        else:  # vectors (the (1, 32) output row too) stay float32
            torch.testing.assert_close(back["actor_state_dict"][key], value, rtol=1e-3, atol=1e-4)  # float16's

    monkeypatch.setattr(simlab.pretrained, "PRETRAINED_DIR", str(out))
    argv = ["play", "--task", TASK, "--use_pretrained_checkpoint", "--headless", "--device", "cpu"]
    argv += ["--num_envs", "2", "--steps", "5", "--log_root", str(tmp_path / "logs")]
    assert run_play(build_parser().parse_args(argv), [])["checkpoint"].startswith(str(tmp_path / "logs"))
    assert script.main(["--restore", "--tasks", "simlab/Cartpole-v0", "--out", str(out)]) == 1  # none shipped there
