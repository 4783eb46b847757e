"""The shipped pretrained policies: ``simlab play --use_pretrained_checkpoint`` plays them at once on
the CPU and they meet the criterion their task registers (``simlab.tasks.utils.criteria``)."""

from __future__ import annotations

import os
import re

import pytest

from simlab.cli.main import build_parser
from simlab.cli.play import run_play
from simlab.pretrained import list_pretrained, pretrained_record
from simlab.tasks.utils.criteria import criterion_for

# Every shipped policy played to its criterion is a learning check of the slow set (minutes in all on
# the 2-core machine); the cartpole's (seconds) keeps the path in the default run.
SHIPPED = [pytest.param(*p, marks=() if p[0] == "simlab/Cartpole-v0" else pytest.mark.slow) for p in list_pretrained()]


@pytest.mark.parametrize(("task", "library"), SHIPPED)
def test_pretrained_policy_meets_its_criterion(tmp_path, task, library):
    record = pretrained_record(task, library)
    # the play make_pretrained.py judged on the CPU (the first cartpoles: 64 envs for 5 s)
    play = record["cpu_evaluation"] if record else {"envs": 64, "seconds": 5.0, "seed": 42}
    criterion = criterion_for(task, record.get("reward_threshold") if record else None)
    argv = ["play", "--task", task, "--library", library, "--use_pretrained_checkpoint", "--headless"]
    argv += ["--device", "cpu", "--num_envs", str(play["envs"]), "--seconds", str(play["seconds"])]
    argv += ["--seed", str(play["seed"])]
    argv += ["--log_root", str(tmp_path / "logs")]
    on_step, state = criterion.make_hook()
    result = run_play(build_parser().parse_args(argv), list(criterion.play_overrides), on_step=on_step)
    # the shipped files stay as they are: play copied the run to <log_root>/pretrained/<library>/<task name>
    assert result["checkpoint"].startswith(str(tmp_path / "logs" / "pretrained" / library))
    assert os.path.isfile(os.path.join(os.path.dirname(result["checkpoint"]), "exported", "policy.onnx"))
    score, passed = criterion.judge(result, state)
    assert passed, f"{task}: {criterion.description}: {score:.3f}"
    argv[argv.index("--use_pretrained_checkpoint")] = "--use_last_checkpoint"
    with pytest.raises(FileNotFoundError):  # the copy is not taken for a training run of the user's
        run_play(build_parser().parse_args(argv), [])


def test_a_task_without_a_pretrained_policy_says_what_is_shipped(tmp_path, capsys):
    from simlab.cli.main import main

    task = "simlab/Reach-Franka-v0"  # its rsl_rl policy ships, an skrl one does not
    argv = ["play", "--task", task, "--library", "skrl", "--use_pretrained_checkpoint", "--device", "cpu"]
    assert main([*argv, "--log_root", str(tmp_path / "logs")]) == 2
    err = capsys.readouterr().err
    assert err.strip().endswith(
        f"No pretrained skrl policy for {task}. Shipped for it: rsl_rl (simlab play --library rsl_rl)."
    )
    task = "simlab/Stack-Cube-Franka-v0"  # none ships (it learns from demonstrations): every shipped policy is named
    argv[argv.index("simlab/Reach-Franka-v0")] = task
    assert main([*argv, "--log_root", str(tmp_path / "logs")]) == 2
    err = capsys.readouterr().err
    assert f"No pretrained skrl policy for {task}. Shipped: " in err and "simlab/Reach-Franka-v0 (rsl_rl)" in err


def test_a_misspelled_task_with_pretrained_is_named_unknown(tmp_path, capsys):
    from simlab.cli.main import main

    argv = ["play", "--task", "simlab/Velocity-Flat-G2-v0", "--use_pretrained_checkpoint", "--device", "cpu"]
    assert main([*argv, "--log_root", str(tmp_path / "logs")]) == 2
    err = capsys.readouterr().err
    assert "Unknown task 'simlab/Velocity-Flat-G2-v0'" in err and "simlab/Velocity-Flat-G1-v0" in err
    assert "Train one with" not in err  # no advice to train a task that does not exist


def test_play_on_the_cpu_takes_the_play_variants_env_count(tmp_path, capsys):
    """The training task's 4096 envs made a 200-step CPU video take over 5 minutes (the G1's)."""
    argv = ["play", "--task", "simlab/Reach-Franka-v0", "--use_pretrained_checkpoint", "--headless"]
    argv += ["--device", "cpu", "--steps", "1", "--no_export", "--log_root", str(tmp_path / "logs")]
    run_play(build_parser().parse_args(argv), [])
    assert "Playing 50 envs on the CPU, as simlab/Reach-Franka-Play-v0 does (the task trains 4096)" in (
        capsys.readouterr().out
    )
    run_play(build_parser().parse_args([*argv, "--num_envs", "3"]), [])  # a count given is kept
    assert "envs on the CPU" not in capsys.readouterr().out


def test_play_on_the_cpu_of_many_envs_without_a_play_variant_says_so(capsys):
    from types import SimpleNamespace

    from simlab.cli.play import _play_variant_envs_on_cpu

    env_cfg = SimpleNamespace(sim=SimpleNamespace(device="cpu"), scene=SimpleNamespace(num_envs=8192))
    args = SimpleNamespace(task="simlab/Repose-Cube-Allegro-Direct-v0", num_envs=None)
    _play_variant_envs_on_cpu(args, env_cfg, [])
    assert "Playing the task's 8192 envs on the CPU, which takes a while; --num_envs 16" in capsys.readouterr().out
    assert env_cfg.scene.num_envs == 8192  # said, not changed
    _play_variant_envs_on_cpu(args, env_cfg, ["env.scene.num_envs=8192"])  # asked for: nothing said
    env_cfg.sim.device = "cuda:0"
    _play_variant_envs_on_cpu(args, env_cfg, [])
    assert not capsys.readouterr().out


def test_a_play_variant_plays_the_policy_of_its_task(tmp_path):
    # Isaac Lab's play.py rule: Isaac-Reach-Franka-Play-v0 plays Isaac-Reach-Franka-v0's checkpoint
    argv = ["play", "--task", "simlab/Reach-Franka-Play-v0", "--use_pretrained_checkpoint", "--headless"]
    argv += ["--device", "cpu", "--num_envs", "2", "--steps", "3", "--log_root", str(tmp_path / "logs")]
    result = run_play(build_parser().parse_args(argv), [])
    assert result["checkpoint"].startswith(str(tmp_path / "logs" / "pretrained" / "rsl_rl" / "Reach-Franka-v0"))


def test_isaac_labs_pretrained_checkpoint_lookup_finds_the_shipped_policies(tmp_path, monkeypatch, capsys):
    """Isaac Lab's play scripts call get_published_pretrained_checkpoint(workflow, task); the checkpoint
    is written where Isaac Lab downloads it, .pretrained_checkpoints/ in the working folder."""
    import torch

    from simlab.utils.pretrained_checkpoint import get_published_pretrained_checkpoint, has_pretrained_checkpoint

    monkeypatch.chdir(tmp_path)
    path = get_published_pretrained_checkpoint("rsl_rl", "Isaac-Cartpole-v0")
    assert path.startswith(str(tmp_path / ".pretrained_checkpoints")) and path.endswith(".pt")
    assert torch.load(path, weights_only=True)["actor_state_dict"]["mlp.0.weight"].dtype == torch.float32
    assert has_pretrained_checkpoint("rsl_rl", "Isaac-Velocity-Rough-Unitree-Go2-Play-v0")  # the task's own
    assert get_published_pretrained_checkpoint("rl_games", "Isaac-Cartpole-v0") is None
    assert "unavailable for this task. No pretrained rl_games policy for simlab/Cartpole-v0" in capsys.readouterr().out
    sb3 = get_published_pretrained_checkpoint("sb3", "Isaac-Cartpole-v0")  # SB3's zip, written from policy.pt
    assert sb3.endswith(".zip") and sb3.startswith(str(tmp_path / ".pretrained_checkpoints" / "pretrained" / "sb3"))


def test_each_shipped_policy_is_one_weights_only_file():
    """One stored file per policy, read with weights_only=True, its zip entries deflated (as
    make_pretrained.py writes them); no exports (play makes them)."""
    import zipfile

    import torch

    from simlab.pretrained import POLICY_FILE, pretrained_run_dir
    from simlab.pretrained.weights import FORMAT

    for task, library in list_pretrained():
        folder = pretrained_run_dir(task, library)
        files = [os.path.relpath(os.path.join(r, n), folder) for r, _, names in os.walk(folder) for n in names]
        weights = [f for f in files if f.endswith((".pt", ".pth", ".onnx", ".zip", ".pkl"))]
        assert weights == [POLICY_FILE], f"{task} ({library}): {weights}"
        assert torch.load(os.path.join(folder, POLICY_FILE), weights_only=True)["format"] == FORMAT
        kinds = {entry.compress_type for entry in zipfile.ZipFile(os.path.join(folder, POLICY_FILE)).infolist()}
        assert kinds == {zipfile.ZIP_DEFLATED}, f"{task} ({library}): policy.pt is not deflated (save_policy)"


def test_a_stored_policy_unpacks_to_the_checkpoint_within_half_a_step_of_int8(tmp_path):
    import torch

    from simlab.pretrained.weights import pack_policy, unpack_policy

    torch.manual_seed(0)
    actor = {"mlp.0.weight": torch.randn(64, 10) * 3.0, "mlp.0.bias": torch.randn(64), "zero": torch.zeros(4, 4)}
    # rsl_rl's normalizer keeps (1, N) statistics: features of unlike magnitudes, one int8 scale would zero some
    actor["obs_normalizer._var"] = torch.logspace(-4, 3, 10).reshape(1, 10)
    checkpoint = {"actor_state_dict": actor, "critic_state_dict": {"w": torch.ones(3)}, "iter": 7, "infos": None}
    checkpoint["optimizer_state_dict"] = {"state": {}}
    torch.save(pack_policy(checkpoint, "rsl_rl", "model_7.pt"), tmp_path / "policy.pt")
    name, back = unpack_policy(str(tmp_path / "policy.pt"))
    assert name == "model_7.pt" and set(back) == {"actor_state_dict", "iter", "infos"} and back["iter"] == 7
    restored = back["actor_state_dict"]
    assert torch.equal(restored["mlp.0.bias"], actor["mlp.0.bias"])  # vectors stay float32
    assert torch.equal(restored["zero"], actor["zero"])
    assert torch.equal(restored["obs_normalizer._var"], actor["obs_normalizer._var"])  # a (1, N) row is a vector
    half_step = actor["mlp.0.weight"].abs().amax(dim=1, keepdim=True) / 254
    error = (restored["mlp.0.weight"] - actor["mlp.0.weight"]).abs()
    assert bool((error <= half_step * 1.0001).all()) and float(error.max()) > 0
    torch.save({"actor_state_dict": actor}, tmp_path / "model_7.pt")
    with pytest.raises(ValueError, match="not a stored simlab policy"):
        unpack_policy(str(tmp_path / "model_7.pt"))


def test_a_skrl_multi_agent_policy_is_stored_per_agent(tmp_path):
    """skrl's IPPO / MAPPO checkpoints hold one checkpoint per agent (the handover's two hands): each
    agent's policy and normalizer are kept, its value, normalizers of values and optimizer are not."""
    import torch

    from simlab.pretrained.weights import pack_policy, unpack_policy

    def one_agent(scale: float) -> dict:
        return {
            "policy": {"net.0.weight": scale * torch.ones(8, 5), "log_std_parameter": torch.zeros(3)},
            "value": {"net.0.weight": torch.ones(8, 7)},
            "optimizer": {"state": {}},
            "observation_preprocessor": {"running_mean": torch.ones(5)},
            "value_preprocessor": {"running_mean": torch.ones(1)},
        }

    checkpoint = {"right_hand": one_agent(1.0), "left_hand": one_agent(-2.0)}
    torch.save(pack_policy(checkpoint, "skrl", "checkpoints/agent_16.pt"), tmp_path / "policy.pt")
    name, back = unpack_policy(str(tmp_path / "policy.pt"))
    assert name == "checkpoints/agent_16.pt" and set(back) == {"right_hand", "left_hand"}
    for agent, scale in (("right_hand", 1.0), ("left_hand", -2.0)):
        assert set(back[agent]) == {"policy", "observation_preprocessor"}
        torch.testing.assert_close(back[agent]["policy"]["net.0.weight"], scale * torch.ones(8, 5))
    with pytest.raises(KeyError, match="has no \\['policy'\\]"):  # neither one policy nor one per agent
        pack_policy({"right_hand": {"value": {}}}, "skrl", "checkpoints/agent_16.pt")


def test_an_sb3_policy_is_stored_without_pickled_code_and_loads_back(tmp_path, monkeypatch):
    """SB3's zip as policy.pt: the policy's weights, the settings as JSON with only the spaces' pickles
    (no policy class, schedule or buffers), the VecNormalize statistics; play's loader reads it back."""
    import json
    import tempfile
    import zipfile

    import gymnasium as gym
    import numpy as np
    import torch

    pytest.importorskip("stable_baselines3")
    from stable_baselines3 import PPO
    from stable_baselines3.common.logger import Logger
    from stable_baselines3.common.vec_env import DummyVecEnv

    from simlab.cli.libraries.sb3 import _safe_objects
    from simlab.pretrained.weights import pack_policy, read_checkpoint, unpack_policy, write_checkpoint

    net = {"net_arch": [8]}
    model = PPO("MlpPolicy", DummyVecEnv([lambda: gym.make("Pendulum-v1")]), n_steps=8, batch_size=8, policy_kwargs=net)
    # SB3's default logger makes a folder <temp>/SB3-<date> when a model learns (left empty in /tmp):
    # one that writes nothing, as simlab's train gives its own (TensorBoard in the run folder)
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    monkeypatch.delenv("SB3_LOGDIR", raising=False)
    model.set_logger(Logger(folder=None, output_formats=[]))
    model.learn(8)  # an optimizer step: Adam's moments exist, and are not stored
    assert not list(tmp_path.glob("SB3-*"))
    (tmp_path / "run").mkdir()
    model.save(tmp_path / "run" / "model_8_steps.zip")
    statistics = {"obs/mean": np.arange(3.0), "obs/var": np.ones(3), "obs/count": np.asarray(9.0), "clip_obs": 5.0}
    np.savez(tmp_path / "run" / "model_vecnormalize_8_steps.npz", **statistics)
    checkpoint = read_checkpoint(str(tmp_path / "run" / "model_8_steps.zip"), "sb3")
    stored = pack_policy(checkpoint, "sb3", "model_8_steps.zip")
    torch.save(stored, tmp_path / "policy.pt")
    name, back = unpack_policy(str(tmp_path / "policy.pt"))  # weights_only=True
    (tmp_path / "out").mkdir()
    path = str(tmp_path / "out" / name)
    write_checkpoint(back, path, "sb3")
    data = json.loads(zipfile.ZipFile(path).read("data"))
    assert data["policy_class"][":serialized:"] == "" and data["lr_schedule"][":serialized:"] == ""
    assert data["observation_space"][":serialized:"] and "_last_obs" not in data
    assert torch.load(tmp_path / "policy.pt", weights_only=True)["state"]["policy.optimizer"]["state"] == {}
    loaded = PPO.load(path, custom_objects=_safe_objects(path, {"policy_kwargs": net}, trust=False))
    for key, value in model.policy.state_dict().items():
        step = value.abs().max() / 127 if value.dim() >= 2 else 0  # int8 rows
        assert float((loaded.policy.state_dict()[key] - value).abs().max()) <= float(step) + 1e-6, key
    with np.load(tmp_path / "out" / "model_vecnormalize_8_steps.npz") as back_statistics:
        assert all(np.array_equal(back_statistics[k], v) for k, v in statistics.items())


def test_rsl_rl_records_count_iterations_as_make_pretrained_or_say_what_their_number_is():
    """``iterations`` is the updates run: rsl_rl's ``model_<N>.pt`` is saved after its (N+1)-th update, so
    make_pretrained writes N + 1. A record whose number was counted otherwise says so in ``iterations_note``."""
    for task, library in list_pretrained():
        record = pretrained_record(task, library)
        if library != "rsl_rl" or record is None:
            continue
        number = int(re.fullmatch(r"model_(\d+)\.pt", record["checkpoint"]).group(1))
        assert record["iterations"] == number + 1 or record.get("iterations_note"), (task, record["iterations"])


def test_play_without_library_plays_the_tasks_only_shipped_policy(tmp_path, capsys):
    """Stack-Cube-Franka-IK-Rel-v0 ships a bc policy only: --use_pretrained_checkpoint plays it without
    --library bc, and says so."""
    task = "simlab/Stack-Cube-Franka-IK-Rel-v0"
    argv = ["play", "--task", task, "--use_pretrained_checkpoint", "--headless", "--device", "cpu"]
    argv += ["--num_envs", "2", "--steps", "2", "--no_export", "--log_root", str(tmp_path / "logs")]
    result = run_play(build_parser().parse_args(argv), [])
    assert result["checkpoint"].startswith(str(tmp_path / "logs" / "pretrained" / "bc"))
    assert f"Playing the bc policy shipped for {task} (--library bc)." in capsys.readouterr().out


def test_play_without_library_of_a_task_shipping_several_takes_rsl_rl():
    from simlab.cli.play import choose_library
    from simlab.pretrained import pretrained_libraries

    assert pretrained_libraries("simlab/Cartpole-v0") == ["rsl_rl", "sb3", "skrl"]
    parse = build_parser().parse_args
    assert choose_library(parse(["play", "--task", "simlab/Cartpole-v0", "--use_pretrained_checkpoint"])) == "rsl_rl"
    given = ["play", "--task", "simlab/Stack-Cube-Franka-IK-Rel-v0", "--use_pretrained_checkpoint", "--library", "skrl"]
    assert choose_library(parse(given)) == "skrl"  # as given: the error then lists what ships
    assert choose_library(parse(["play", "--task", "simlab/Stack-Cube-Franka-IK-Rel-v0"])) == "rsl_rl"
