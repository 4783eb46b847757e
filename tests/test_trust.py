"""Someone else's file cannot run code here (issue 37.1-3, 5 and overrides), written as the attack.

Each crafted file holds a pickle whose ``__reduce__`` creates a marker file when unpickled: the
marker must not appear, and the refusal is one line (exit 2). Real checkpoints of the four
libraries still load and play.
"""

from __future__ import annotations

import base64
import dataclasses
import glob
import json
import os
import pickle
import shutil
import zipfile

import pytest
import torch

from simlab.cli.main import main
from simlab.utils.errors import UntrustedFileError

TASK = "simlab/Cartpole-v0"
SMALL = ["--task", TASK, "--num_envs", "4", "--headless", "--device", "cpu"]
# what the cartpole's policy sees without its joint velocities: 2 observations instead of 4
FEWER_OBS = "env.observations.policy.joint_vel_rel=null"


class MakesAFile:
    """Unpickling this creates ``path``: what a crafted checkpoint would do (with a shell command)."""

    def __init__(self, path: str):
        self.path = path

    def __reduce__(self):
        return (open, (self.path, "w"))


def _main(tmp_path, *argv: str) -> int:
    return main([*argv, "--log_root", str(tmp_path / "logs")])


def _one_line_error(capsys) -> str:
    err = [line for line in capsys.readouterr().err.splitlines() if line.startswith("simlab ")]
    assert len(err) == 1, err
    return err[0]


@pytest.fixture(scope="module")
def runs(tmp_path_factory) -> dict[str, str]:
    """One tiny run of each library on the cartpole (2 iterations, 4 envs): library -> its run folder;
    "sb3_norm": an SB3 run with VecNormalize."""
    root = tmp_path_factory.mktemp("trust_runs")
    found = {}
    for name, library, extra in (
        ("rsl_rl", "rsl_rl", []),
        ("skrl", "skrl", []),
        ("sb3", "sb3", []),
        ("rl_games", "rl_games", []),
        ("sb3_norm", "sb3", ["+agent.normalize_input=true"]),
    ):
        log_root = str(root / name)
        code = main(["train", *SMALL, "--library", library, "--max_iterations", "2", "--log_root", log_root, *extra])
        assert code == 0, name
        (found[name],) = glob.glob(os.path.join(log_root, library, "*", "*"))
    return found


def _checkpoint(run: str, library: str) -> str:
    pattern = {"rsl_rl": "model_*.pt", "skrl": "checkpoints/agent_*.pt", "sb3": "model.zip", "rl_games": "nn/*.pth"}
    return sorted(glob.glob(os.path.join(run, pattern[library])))[-1]


# --- 1. checkpoints load weights only -------------------------------------------------------------


def _crafted_torch_file(path, marker, real: dict | None = None) -> str:
    torch.save({**(real or {"iter": 1}), "extra": MakesAFile(str(marker))}, str(path))
    assert not os.path.exists(marker)
    return str(path)


def test_play_refuses_a_crafted_checkpoint(tmp_path, capsys, runs):
    marker = tmp_path / "pwned"
    real = torch.load(_checkpoint(runs["rsl_rl"], "rsl_rl"), weights_only=True)
    crafted = _crafted_torch_file(tmp_path / "model_1.pt", marker, real)
    assert _main(tmp_path, "play", *SMALL, "--checkpoint", crafted, "--steps", "2") == 2
    line = _one_line_error(capsys)
    assert "Refused" in line and "--trust_checkpoint" in line and "io.open" in line
    assert not marker.exists()


def test_use_last_checkpoint_refuses_a_crafted_newest_checkpoint(tmp_path, capsys, runs):
    marker = tmp_path / "pwned"
    run = tmp_path / "logs" / "rsl_rl" / "cartpole" / "2099-01-01_00-00-00"
    shutil.copytree(runs["rsl_rl"], run)
    _crafted_torch_file(run / "model_999.pt", marker)
    assert _main(tmp_path, "play", *SMALL, "--use_last_checkpoint", "--steps", "2") == 2
    assert "--trust_checkpoint" in _one_line_error(capsys)
    assert not marker.exists()


def test_train_refuses_to_resume_from_a_crafted_checkpoint(tmp_path, capsys):
    marker = tmp_path / "pwned"
    crafted = _crafted_torch_file(tmp_path / "model_5.pt", marker)
    code = _main(tmp_path, "train", *SMALL, "--checkpoint", crafted, "--max_iterations", "1")
    assert code == 2 and "--trust_checkpoint" in _one_line_error(capsys)
    assert not marker.exists()
    assert not glob.glob(str(tmp_path / "logs" / "rsl_rl" / "*" / "*"))  # no run folder either


def test_rl_games_refuses_a_crafted_checkpoint(tmp_path, capsys):
    marker = tmp_path / "pwned"
    crafted = _crafted_torch_file(tmp_path / "last_cartpole_ep_2.pth", marker, {"model": {}, "epoch": 2})
    code = _main(tmp_path, "play", *SMALL, "--library", "rl_games", "--checkpoint", crafted, "--steps", "2")
    assert code == 2 and "--trust_checkpoint" in _one_line_error(capsys)
    assert not marker.exists()
    # the adapter's own loader (rl_games' restore asks torch for weights_only=False) loads weights only too
    from simlab.cli.libraries.rl_games import _restore_on_device

    with pytest.raises(UntrustedFileError):
        _restore_on_device(None, crafted, "cpu")
    assert not marker.exists()


def test_libraries_own_loads_read_a_weights_only_copy(tmp_path):
    """rsl_rl, skrl and rl_games call torch.load(weights_only=False) themselves (skrl on JAX pickle.load):
    they get a copy written from what a weights-only load read, torch.load itself stays as it is, and
    --trust_checkpoint (trust=True) hands them the file itself."""
    from simlab.utils.trust import weights_only_copy

    marker = tmp_path / "pwned"
    crafted = _crafted_torch_file(tmp_path / "model.pt", marker)
    with pytest.raises(UntrustedFileError, match="io.open"), weights_only_copy(crafted):
        pass
    assert not marker.exists()
    with open(tmp_path / "agent_5.pickle", "wb") as f:  # skrl on JAX: a pickled dict of flax bytes
        pickle.dump({"policy": MakesAFile(str(marker))}, f, protocol=4)
    with (
        pytest.raises(UntrustedFileError, match="io.open"),
        weights_only_copy(str(tmp_path / "agent_5.pickle"), kind="pickle"),
    ):
        pass
    assert not marker.exists()

    real = {"policy": {"w": torch.arange(3.0)}, "iter": 7}
    torch.save(real, str(tmp_path / "agent_7.pt"))
    with weights_only_copy(str(tmp_path / "agent_7.pt")) as path:
        assert torch.load is torch.serialization.load  # nothing patched while the library loads
        assert os.path.basename(path) == "agent_7.pt" and path != str(tmp_path / "agent_7.pt")
        loaded = torch.load(path, weights_only=False)  # what the libraries do
    assert loaded["iter"] == 7 and torch.equal(loaded["policy"]["w"], real["policy"]["w"])
    assert not os.path.exists(path)  # the copy is gone after the block
    with open(tmp_path / "agent_8.pickle", "wb") as f:
        pickle.dump({"policy": b"flax bytes", "value": b"more"}, f, protocol=4)
    with weights_only_copy(str(tmp_path / "agent_8.pickle"), kind="pickle") as path, open(path, "rb") as f:
        assert pickle.load(f) == {"policy": b"flax bytes", "value": b"more"}

    with weights_only_copy(crafted, trust=True) as path:
        torch.load(path, weights_only=False)
    assert marker.exists()  # the user vouched for the file: it loads as the library would


@pytest.mark.parametrize("library", ["skrl", "rl_games"])
def test_resume_and_play_refuse_a_crafted_checkpoint_of_each_library(tmp_path, capsys, runs, library):
    """The libraries' own resume and play paths (rsl_rl's: the tests above) never unpickle the crafted part."""
    from simlab.utils.trust import torch_load

    marker = tmp_path / "pwned"
    real_path = _checkpoint(runs[library], library)
    real = torch_load(real_path, map_location="cpu")  # rl_games keeps numpy scalars: simlab's load reads them
    crafted = _crafted_torch_file(tmp_path / os.path.basename(real_path), marker, real)
    common = [*SMALL, "--library", library, "--checkpoint", crafted]
    assert _main(tmp_path, "play", *common, "--steps", "2") == 2
    assert "--trust_checkpoint" in _one_line_error(capsys)
    assert _main(tmp_path, "train", *common, "--max_iterations", "1") == 2
    assert "--trust_checkpoint" in _one_line_error(capsys)
    assert not marker.exists()


def test_numpy_values_real_checkpoints_hold_still_load(tmp_path):
    """rl_games keeps its best mean reward as a numpy scalar once episodes finish: weights-only loads take it."""
    import numpy as np

    from simlab.utils.trust import torch_load

    state = {"model": {"w": torch.ones(2)}, "epoch": 3, "last_mean_rewards": np.float32(1.5), "a": np.zeros(3)}
    torch.save(state, str(tmp_path / "rl_games.pth"))
    loaded = torch_load(str(tmp_path / "rl_games.pth"))
    assert loaded["last_mean_rewards"] == np.float32(1.5) and loaded["a"].shape == (3,)


def _crafted_sb3_zip(real: str, path, key: str, payload: object) -> str:
    """``real`` with its ``data`` item ``key`` replaced by a cloudpickle-style serialized ``payload``."""
    with zipfile.ZipFile(real) as z:
        members = {name: z.read(name) for name in z.namelist()}
    data = json.loads(members["data"])
    data[key] = {":type:": "<class 'object'>", ":serialized:": base64.b64encode(pickle.dumps(payload)).decode()}
    members["data"] = json.dumps(data).encode()
    with zipfile.ZipFile(path, "w") as z:
        for name, content in members.items():
            z.writestr(name, content)
    return str(path)


@pytest.mark.parametrize("key", ["clip_range", "policy_class", "observation_space", "policy_extra_item"])
def test_sb3_never_unpickles_a_crafted_zip(tmp_path, capsys, runs, key):
    """Settings the task's config gives (clip_range, the policy class) are taken from it and the file's
    are never unpickled; the spaces go through a restricted unpickler; anything else is refused."""
    marker = tmp_path / "pwned"
    crafted = _crafted_sb3_zip(_checkpoint(runs["sb3"], "sb3"), tmp_path / "model.zip", key, MakesAFile(str(marker)))
    code = _main(tmp_path, "play", *SMALL, "--library", "sb3", "--checkpoint", crafted, "--steps", "2", "--no_export")
    if key in ("clip_range", "policy_class"):
        assert code == 0  # the config's value is used: the crafted one is never read
    else:
        assert code == 2 and "--trust_checkpoint" in _one_line_error(capsys)
    assert not marker.exists()


def test_sb3_refuses_pickled_normalizer_statistics(tmp_path, capsys, runs):
    marker = tmp_path / "pwned"
    run = tmp_path / "run"
    shutil.copytree(runs["sb3_norm"], run)
    for stats in glob.glob(str(run / "model_vecnormalize*.npz")):
        os.remove(stats)  # a run of SB3's own format: statistics pickled beside the model
    with open(run / "model_vecnormalize.pkl", "wb") as f:
        pickle.dump(MakesAFile(str(marker)), f)
    argv = ["play", *SMALL, "--library", "sb3", "--checkpoint", str(run / "model.zip"), "--steps", "2"]
    assert _main(tmp_path, *argv, "+agent.normalize_input=true") == 2
    line = _one_line_error(capsys)
    assert "model_vecnormalize.pkl" in line and "--trust_checkpoint" in line
    assert not marker.exists()


def test_sb3_normalizer_statistics_are_plain_arrays(runs, tmp_path):
    import numpy as np

    from simlab.cli.libraries.sb3 import load_statistics

    run = runs["sb3_norm"]
    assert not glob.glob(os.path.join(run, "*.pkl"))
    with np.load(os.path.join(run, "model_vecnormalize.npz"), allow_pickle=False) as data:
        assert data["obs/mean"].shape == (4,) and float(data["obs/count"]) > 1
        stats = load_statistics(os.path.join(run, "model.zip"))
        assert np.array_equal(stats["obs"][""].var, data["obs/var"]) and stats["norm_obs"] is True
        assert stats["clip_obs"] == float(data["clip_obs"])


# --- real checkpoints still load, play and resume -------------------------------------------------


@pytest.mark.parametrize("name", ["rsl_rl", "skrl", "sb3", "rl_games", "sb3_norm"])
def test_real_checkpoints_of_each_library_play(tmp_path, runs, name):
    library = "sb3" if name == "sb3_norm" else name
    extra = ["+agent.normalize_input=true"] if name == "sb3_norm" else []
    checkpoint = _checkpoint(runs[name], library)
    argv = ["play", *SMALL, "--library", library, "--checkpoint", checkpoint, "--steps", "3", "--no_export"]
    assert _main(tmp_path, *argv, *extra) == 0


def test_sb3_resumes_from_its_checkpoint_and_statistics(tmp_path, capsys, runs):
    argv = ["train", *SMALL, "--library", "sb3", "--max_iterations", "1", "--checkpoint", runs["sb3_norm"]]
    assert _main(tmp_path, *argv, "+agent.normalize_input=true") == 0
    assert "Resumed from" in capsys.readouterr().out


# --- 2. shipped policies come from the package only -----------------------------------------------


def test_a_planted_pretrained_checkpoint_is_ignored(tmp_path, capsys):
    marker = tmp_path / "pwned"
    planted = tmp_path / "logs" / "pretrained" / "rsl_rl" / "Cartpole-v0"
    planted.mkdir(parents=True)
    _crafted_torch_file(planted / "model_99999.pt", marker)  # newer than the shipped one's name
    argv = ["play", *SMALL, "--use_pretrained_checkpoint", "--steps", "2", "--no_export"]
    assert _main(tmp_path, *argv) == 0
    out = capsys.readouterr().out
    assert "model_99999" not in out and "Playing" in out
    assert not marker.exists()


# --- 5. a checkpoint of another task: one line naming the layer and both sizes ---------------------


@pytest.mark.parametrize("library", ["rsl_rl", "skrl", "sb3", "rl_games"])
def test_a_checkpoint_of_another_task_is_refused_in_one_line(tmp_path, capsys, runs, library):
    real = _checkpoint(runs[library], library)
    copied = str(tmp_path / os.path.basename(real))  # out of its run folder: no params/run.yaml beside it
    shutil.copy(real, copied)
    argv = ["play", *SMALL, "--library", library, "--checkpoint", copied, "--steps", "2", FEWER_OBS]
    assert _main(tmp_path, *argv) == 2
    line = _one_line_error(capsys)
    assert "layer '" in line and "does not fit" in line, line
    assert "4" in line.split("size")[1] and "2" in line.split("policy")[-1], line  # both sizes


# --- overrides: module:name resolves inside simlab, the task's package and --allow_module ----------


def test_an_override_naming_another_module_is_refused(tmp_path, capsys):
    argv = ["train", *SMALL, "--max_iterations", "1", "env.rewards.alive.func=pydoc:pipepager"]
    assert _main(tmp_path, *argv) == 2
    line = _one_line_error(capsys)
    assert "'pydoc'" in line and "--allow_module pydoc" in line


def test_a_refused_module_is_never_imported():
    import sys

    from simlab.utils.string import callable_modules, string_to_callable

    assert "antigravity" not in sys.modules  # importing it opens a web browser
    with callable_modules(["simlab"]), pytest.raises(ValueError, match="--allow_module antigravity"):
        string_to_callable("antigravity:geohash")
    assert "antigravity" not in sys.modules
    with callable_modules(["simlab"]):
        assert callable(string_to_callable("simlab.envs.mdp:joint_pos_rel"))
    assert string_to_callable("os.path:join") is os.path.join  # Python code outside the block names any


def test_allow_module_lets_an_override_name_that_module(tmp_path, capsys, monkeypatch):
    package = tmp_path / "trusted_rewards"
    package.mkdir()
    (package / "__init__.py").write_text(
        "import torch\n\ndef alive(env):\n    return torch.ones(env.num_envs, device=env.device)\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    argv = ["train", *SMALL, "--max_iterations", "1", "env.rewards.alive.func=trusted_rewards:alive"]
    assert _main(tmp_path, *argv) == 2
    assert "--allow_module trusted_rewards" in _one_line_error(capsys)
    assert _main(tmp_path, *argv, "--allow_module", "trusted_rewards") == 0


def test_bench_solve_refuses_another_module_and_takes_allow_module(tmp_path, capsys):
    from simlab.benchmarks.solve import time_to_policy

    bench = ["bench", "solve", "--tasks", TASK, "--device", "cpu", "--num_envs", "4", "--max_iterations", "1"]
    bench += ["--log_root", str(tmp_path / "logs")]
    assert main([*bench, "--overrides", "env.rewards.alive.func=pydoc:pipepager"]) != 0
    assert "--allow_module pydoc" in capsys.readouterr().err
    # the flag reaches the training it runs: the module is allowed there (then os.getcwd is no reward term)
    with pytest.raises(Exception) as allowed:
        time_to_policy(
            TASK, num_envs=4, max_iterations=1, log_root=str(tmp_path / "logs"),
            overrides=["env.rewards.alive.func=os:getcwd"], allow_module=["os"],
        )  # fmt: skip
    assert "--allow_module" not in str(allowed.value)


def test_isaac_lab_scripts_pass_the_trust_flags_on():
    from simlab.cli.isaaclab_scripts import build_script_parser, script_to_simlab_argv

    args, rest = build_script_parser("rl_games", "play").parse_known_args(
        ["--task", "Isaac-Cartpole-v0", "--trust_checkpoint", "--allow_module", "mypkg", "--checkpoint", "m.pth"]
    )
    argv = script_to_simlab_argv("rl_games", "play", args, rest)
    assert "--trust_checkpoint" in argv and argv[argv.index("--allow_module") + 1] == "mypkg"


def _sb3_run_with_pickled_statistics(runs, tmp_path, payload) -> str:
    """A copy of the SB3 VecNormalize run whose statistics are a pickle (SB3's own format) of ``payload``."""
    run = tmp_path / "run"
    shutil.copytree(runs["sb3_norm"], run)
    for stats in glob.glob(str(run / "model_vecnormalize*.npz")):
        os.remove(stats)
    for name in ("model_vecnormalize.pkl", "model_vecnormalize_128_steps.pkl"):
        with open(run / name, "wb") as f:
            pickle.dump(payload, f)
    return str(run)


def test_train_refuses_pickled_statistics_when_resuming(tmp_path, capsys, runs):
    marker = tmp_path / "pwned"
    run = _sb3_run_with_pickled_statistics(runs, tmp_path, MakesAFile(str(marker)))
    argv = ["train", *SMALL, "--library", "sb3", "--max_iterations", "1", "--checkpoint", run]
    assert _main(tmp_path, *argv, "+agent.normalize_input=true") == 2
    assert "--trust_checkpoint" in _one_line_error(capsys)
    assert not marker.exists()


def test_trust_checkpoint_loads_sb3s_own_pickled_statistics(tmp_path, capsys, runs):
    """An SB3 run of the old format (VecNormalize pickled by SB3's save) plays once the user vouches for it."""
    import gymnasium as gym
    from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

    normalizer = VecNormalize(DummyVecEnv([lambda: gym.make("CartPole-v1")]))  # 4 observations, as the cartpole's
    normalizer.obs_rms.mean[:] = 0.5
    run = _sb3_run_with_pickled_statistics(runs, tmp_path, None)
    normalizer.save(os.path.join(run, "model_vecnormalize.pkl"))
    argv = ["play", *SMALL, "--library", "sb3", "--checkpoint", os.path.join(run, "model.zip"), "--steps", "2"]
    argv += ["--no_export", "+agent.normalize_input=true"]
    assert _main(tmp_path, *argv) == 2
    assert "model_vecnormalize.pkl" in _one_line_error(capsys)
    assert _main(tmp_path, *argv, "--trust_checkpoint") == 0


def test_load_pickle_reads_data_and_refuses_code(tmp_path):
    from simlab.utils.io import dump_pickle, load_pickle

    marker = tmp_path / "pwned"
    with open(tmp_path / "crafted.pkl", "wb") as f:
        pickle.dump({"cfg": MakesAFile(str(marker))}, f)
    with pytest.raises(UntrustedFileError, match="io.open"):
        load_pickle(tmp_path / "crafted.pkl")
    assert not marker.exists()

    class WritesWithSimlab:  # a simlab function is no more allowed than os.system: it writes a file
        def __reduce__(self):
            from simlab.utils.io import write_text

            return (write_text, (str(marker), "x"))

    dump_pickle(tmp_path / "simlab_call.pkl", WritesWithSimlab())
    with pytest.raises(UntrustedFileError, match="write_text"):
        load_pickle(tmp_path / "simlab_call.pkl")
    assert not marker.exists()

    import numpy as np

    from simlab.sim import SimulationCfg

    data = {"cfg": SimulationCfg(dt=0.01), "x": np.arange(3), "t": (1, 2.0)}
    dump_pickle(tmp_path / "env.pkl", data)
    back = load_pickle(tmp_path / "env.pkl")
    assert back["cfg"].dt == 0.01 and back["x"].tolist() == [0, 1, 2] and back["t"] == (1, 2.0)


@dataclasses.dataclass
class WritesWhenBuilt:
    """A dataclass of a module other than simlab's (a third-party config, say) whose construction has an
    effect: a pickle may call a class it names, so naming it runs ``__post_init__``."""

    path: str

    def __post_init__(self):
        open(self.path, "w").close()


class BuildsIt:
    def __init__(self, path: str):
        self.path = path

    def __reduce__(self):
        return (WritesWhenBuilt, (self.path,))


def test_load_pickle_refuses_dataclasses_outside_simlab_and_the_allowed_packages(tmp_path):
    from simlab.utils.io import load_pickle
    from simlab.utils.string import callable_modules

    marker = tmp_path / "pwned"
    with open(tmp_path / "crafted.pkl", "wb") as f:
        pickle.dump({"cfg": BuildsIt(str(marker))}, f)
    module = WritesWhenBuilt.__module__
    with pytest.raises(UntrustedFileError) as refused:
        load_pickle(tmp_path / "crafted.pkl")
    line = str(refused.value)
    assert "\n" not in line and f"'{module}'" in line and f"--allow_module {module.split('.')[0]}" in line
    with callable_modules(["simlab", "some_task_package"]), pytest.raises(UntrustedFileError):
        load_pickle(tmp_path / "crafted.pkl")  # the command's allowed packages do not include this one
    assert not marker.exists()

    with callable_modules([module.split(".")[0]]):  # --allow_module, or the task's own package
        assert isinstance(load_pickle(tmp_path / "crafted.pkl")["cfg"], WritesWhenBuilt)
    assert marker.exists()
    marker.unlink()
    load_pickle(tmp_path / "crafted.pkl", allow_modules=[module.split(".")[0]])
    assert marker.exists()
