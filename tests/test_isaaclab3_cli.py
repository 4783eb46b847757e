"""Isaac Lab 3.0's command lines on ``simlab train`` / ``play`` (simlab/cli/isaaclab3.py, issue 42.2):
each runs (one iteration, a few envs) or is refused in one line saying what to use."""

from __future__ import annotations

import argparse
import os

import pytest
from conftest import rendering_available

from simlab.cli.isaaclab3 import apply_selectors, apply_visualizer
from simlab.cli.main import main
from simlab.cli.session import load_configs
from simlab.utils.errors import ConfigError
from simlab.utils.string import simlab_task_id

CPU = ["--num_envs", "8", "--device", "cpu", "--viz", "none"]


def _runs(root) -> list[str]:
    folder = os.path.join(root, "rsl_rl", "cartpole")
    return sorted(os.listdir(folder)) if os.path.isdir(folder) else []


def test_isaaclab3_train_then_play_command_lines(tmp_path, capsys):
    logs = str(tmp_path / "logs")
    train = ["train", "--rl_library", "rsl_rl", "--task", "Isaac-Cartpole", *CPU, "physics=mujoco"]
    assert main([*train, "--max_iterations", "1", "--log_root", logs, "env.sim.dt=0.01"]) == 0
    out = capsys.readouterr().out
    assert "[simlab] Task Isaac-Cartpole -> simlab/Cartpole-v0" in out
    assert "[simlab] physics=mujoco -> sim.engine=mujoco on the CPU" in out
    assert len(_runs(logs)) == 1
    play = ["play", "--rl_library", "rsl_rl", "--task", "Isaac-Cartpole", *CPU, "--checkpoint", "latest"]
    assert main([*play, "--steps", "2", "--no_export", "--log_root", logs]) == 0
    assert "[simlab] --checkpoint latest -> --use_last_checkpoint" in capsys.readouterr().out


def test_version_less_ids_take_the_highest_registered_version():
    import simlab.tasks  # noqa: F401 - registers the tasks

    assert simlab_task_id("simlab/Cartpole") == "simlab/Cartpole-v0"
    assert simlab_task_id("Isaac-Cartpole") == "simlab/Cartpole-v0"
    assert simlab_task_id("Isaac-Cartpole-Camera-Direct") == "simlab/Cartpole-Camera-Direct-v0"
    assert simlab_task_id("Isaac-Cartpole-v0") == "simlab/Cartpole-v0"  # 2.x ids as before
    assert simlab_task_id("simlab/Unknown") == "simlab/Unknown"  # left for the registry's own error


@pytest.mark.parametrize(
    ("words", "message"),
    [
        (["physics=physx"], "physics=physx: simlab simulates with MuJoCo: use physics=mujoco"),
        (["physics=isaacsim_physx"], "use physics=mujoco (MuJoCo C on the CPU) or physics=newton_mjwarp"),
        (["presets=physx,rgb"], "physics=physx: simlab simulates with MuJoCo"),
        (["renderer=isaacsim_rtx_renderer"], "use renderer=opengl (MuJoCo's OpenGL renderer) or renderer=newton"),
        (["presets=ovrtx_renderer"], "presets=ovrtx_renderer: simlab renders with MuJoCo"),
        (["--viz", "rerun"], "--viz rerun: simlab has no Rerun recorder: use --viz web"),
        (["--viz", "newton_rtx"], "--viz newton_rtx: simlab has no path-traced viewer"),
        (["--viz", "kit,viser"], "simlab opens one live viewer"),
        (["--viz", "newton_gl,viser"], "simlab opens one live viewer"),
        (["--visualizer", "unknown"], "--viz unknown is not a visualizer simlab knows"),
        (["presets=rgb"], "presets=rgb: not a preset of simlab/Cartpole-v0 (it registers no presets)"),
        (["physics=mujoco", "--device", "cuda"], "physics=mujoco runs on the CPU"),
        (["physics=mujoco", "physics=mujoco"], "physics= is given twice"),
    ],
)
def test_what_simlab_cannot_honour_is_refused_in_one_line(words, message, capsys, tmp_path):
    argv = ["train", "--rl_library", "rsl_rl", "--task", "Isaac-Cartpole", "--num_envs", "8"]
    assert main([*argv, "--max_iterations", "1", "--log_root", str(tmp_path), *words]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("simlab train: error: ") and "\n" not in err, err
    assert message in err
    assert not os.path.exists(tmp_path / "rsl_rl")  # refused before anything was written


def test_play_checkpoint_best_is_refused(capsys):
    argv = ["play", "--rl_library", "rsl_rl", "--task", "Isaac-Cartpole", *CPU, "--checkpoint", "best"]
    assert main(argv) == 2
    assert "--checkpoint best: simlab keeps no best checkpoint" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("value", "kind"),
    [
        ("newton_gl", "native"),
        ("newton", "native"),
        ("kit", "native"),
        ("kit,newton_gl", "native"),
        ("viser", "web"),
        ("none", "none"),
        ("web", "web"),
    ],
)
def test_visualizer_names_map_to_simlab_viewers(value, kind):
    args = argparse.Namespace(visualizer=value, viewer="auto")
    apply_visualizer(args)
    assert args.viewer == kind


def _args(task: str, *selectors: str, device: str | None = "cpu") -> argparse.Namespace:
    args = argparse.Namespace(task=task, library="rsl_rl", algorithm=None, agent=None, num_envs=None, device=device)
    apply_selectors(args, dict(word.split("=", 1) for word in selectors))
    return args


def test_presets_select_the_registered_variant_of_the_camera_cartpole():
    from simlab.tasks.direct.cartpole.cartpole_camera_env import CartpoleDepthCameraEnvCfg, CartpoleRGBCameraEnvCfg

    task = "simlab/Cartpole-Camera-Direct-v0"
    depth, _ = load_configs(_args(task, "presets=depth"), [])
    rgb, _ = load_configs(_args(task, "presets=rgb"), [])
    default, _ = load_configs(_args(task), [])
    assert type(depth) is CartpoleDepthCameraEnvCfg and type(rgb) is CartpoleRGBCameraEnvCfg
    assert type(default) is CartpoleRGBCameraEnvCfg  # 3.0's default preset of this task is rgb
    both, _ = load_configs(_args(task, "presets=newton_mjwarp,depth"), [])  # 3.0's benchmark form
    assert type(both) is CartpoleDepthCameraEnvCfg and both.sim.engine == "mujoco_warp"
    with pytest.raises(ConfigError, match=r"presets=albedo: not a preset of .* \(its presets are depth, rgb\)"):
        load_configs(_args(task, "presets=albedo"), [])


def test_physics_and_renderer_selectors():
    env_cfg, _ = load_configs(_args("simlab/Cartpole-v0", "physics=newton_mjwarp"), [])
    assert env_cfg.sim.engine == "mujoco_warp"
    args = _args("simlab/Cartpole-v0", "physics=mujoco", device=None)
    env_cfg, _ = load_configs(args, [])
    assert env_cfg.sim.engine == "mujoco" and env_cfg.sim.device == "cpu"
    assert _args("simlab/Cartpole-v0", "renderer=newton_renderer").renderer == "warp"
    assert _args("simlab/Cartpole-v0", "renderer=opengl").renderer == "opengl"


def test_renderer_selector_holds_for_the_command_only(monkeypatch):
    from simlab.cli.isaaclab3 import renderer_choice

    monkeypatch.delenv("SIMLAB_RENDERER", raising=False)
    with renderer_choice("warp"):
        assert os.environ["SIMLAB_RENDERER"] == "warp"
    assert "SIMLAB_RENDERER" not in os.environ


@pytest.mark.skipif(not rendering_available(), reason="needs offscreen rendering (EGL or OSMesa)")
def test_the_camera_cartpole_trains_with_a_preset(tmp_path, capsys):
    argv = ["train", "--rl_library", "rsl_rl", "--task", "Isaac-Cartpole-Camera-Direct", "--num_envs", "2"]
    argv += ["--device", "cpu", "--viz", "none", "--max_iterations", "1", "--log_root", str(tmp_path), "presets=depth"]
    argv += ["agent.num_steps_per_env=4", "agent.algorithm.num_mini_batches=2"]
    assert main(argv) == 0
    assert "[simlab] presets: depth" in capsys.readouterr().out
    params = next((tmp_path / "rsl_rl").rglob("env.yaml")).read_text()
    assert "- depth" in params  # the depth variant's camera


def test_isaaclab3_unified_scripts(tmp_path):
    """Isaac Lab 3.0's scripts/reinforcement_learning/train.py and play.py (its `isaaclab train/play`)."""
    import subprocess
    import sys

    scripts = os.path.join(
        os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scripts", "reinforcement_learning"
    )
    common = ["--rl_library", "rsl_rl", "--task", "Isaac-Cartpole", *CPU, "--log_root", str(tmp_path)]
    train = [sys.executable, os.path.join(scripts, "train.py"), *common, "--max_iterations", "1", "physics=mujoco"]
    done = subprocess.run(train, capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    assert "[simlab] Task Isaac-Cartpole -> simlab/Cartpole-v0" in done.stdout
    play = [sys.executable, os.path.join(scripts, "play.py"), *common, "--checkpoint", "latest", "--steps", "2"]
    done = subprocess.run([*play, "--no_export"], capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    refused = [*train[:-1], "physics=physx"]
    refused = subprocess.run(refused, capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert refused.returncode == 2 and refused.stderr.strip().count("\n") == 0
    assert "physics=physx: simlab simulates with MuJoCo" in refused.stderr


def test_isaaclab3_app_launcher_name():
    import argparse as ap

    from simlab.app import add_launcher_args

    parser = ap.ArgumentParser()
    add_launcher_args(parser)
    assert parser.parse_args(["--device", "cpu"]).device == "cpu"


def test_isaaclab3_cartpole_tutorial_runs_by_the_mapping(tmp_path):
    """Isaac Lab 3.0's run_cartpole_rl_env.py tutorial, its imports mapped (tests/ported3): add_launcher_args,
    launch_simulation, parse_env_cfg with trailing overrides, instantiate, env.sim.is_running()."""
    import subprocess
    import sys

    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "ported3", "run_cartpole_rl_env.py")
    argv = [sys.executable, script, "--num_envs", "4", "--device", "cpu", "--viz", "none", "--max_app_steps", "20"]
    done = subprocess.run([*argv, "physics=mujoco"], capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    assert done.stdout.count("[Env 0]: Pole joint:") == 20 and done.stdout.count("Resetting environment") == 1


def test_parse_env_cfg_takes_isaaclab3_overrides_and_ids():
    from simlab.tasks.direct.cartpole.cartpole_camera_env import CartpoleDepthCameraEnvCfg
    from simlab.tasks.utils import parse_env_cfg

    cfg = parse_env_cfg("simlab/Cartpole", device="cpu", num_envs=4, overrides=["physics=mujoco", "sim.dt=0.01"])
    assert cfg.sim.engine == "mujoco" and cfg.sim.dt == 0.01 and cfg.scene.num_envs == 4
    cfg = parse_env_cfg("simlab/Cartpole-Camera-Direct", device="cpu", overrides=["presets=newton_mjwarp,depth"])
    assert type(cfg) is CartpoleDepthCameraEnvCfg and cfg.sim.engine == "mujoco_warp"
    with pytest.raises(ConfigError, match="physics=isaacsim_physx: simlab simulates with MuJoCo"):
        parse_env_cfg("simlab/Cartpole", device="cpu", overrides=["physics=isaacsim_physx"])


def test_instantiate_makes_the_env_a_config_describes():
    from simlab.envs import ManagerBasedRLEnv
    from simlab.sim import SimulationContext
    from simlab.tasks.utils import parse_env_cfg
    from simlab.utils import instantiate

    env = instantiate(parse_env_cfg("simlab/Cartpole", device="cpu", num_envs=2))
    try:
        assert isinstance(env, ManagerBasedRLEnv) and env.sim.is_running()  # no app: the loop runs
    finally:
        env.close()
        SimulationContext.clear_instance()
    with pytest.raises(ConfigError, match="names no class to make"):
        instantiate(object())
