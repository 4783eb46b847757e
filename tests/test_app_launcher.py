"""AppLauncher: flags, settings, the is_running() bound and Ctrl+C handling."""

from __future__ import annotations

import argparse
import signal

import pytest

from simlab.app import AppLauncher, resolve_device


@pytest.fixture
def launchers():
    """Close every launcher a test creates, so SIGINT handlers never leak between tests."""
    made: list[AppLauncher] = []

    def make(*args, **kwargs) -> AppLauncher:
        made.append(AppLauncher(*args, **kwargs))
        return made[-1]

    yield make
    for launcher in reversed(made):
        launcher.app.close()


def make_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser()
    AppLauncher.add_app_launcher_args(parser)
    return parser


def test_flags_defaults():
    args = make_parser().parse_args([])
    assert args.headless is False and args.enable_cameras is False and args.verbose is False
    assert args.device is None and args.max_app_steps is None and args.livestream == -1


def test_flags_parsed(launchers):
    args = make_parser().parse_args(["--headless", "--device", "cpu", "--enable_cameras", "--max_app_steps", "3"])
    launcher = launchers(args)
    assert launcher.headless and launcher.enable_cameras
    assert launcher.device == "cpu" and launcher.max_app_steps == 3


def test_existing_device_flag_is_kept():
    parser = argparse.ArgumentParser()
    parser.add_argument("--device", type=str, default="cpu", help="script's own")
    parser.add_argument("--num_envs", type=int, default=16)
    AppLauncher.add_app_launcher_args(parser)  # must not raise argparse.ArgumentError
    args = parser.parse_args(["--headless"])
    assert args.device == "cpu" and args.headless and args.num_envs == 16


def test_namespace_dict_and_kwargs(launchers):
    ns = argparse.Namespace(headless=True, device="cpu", num_envs=8)  # script flags are ignored
    assert launchers(ns).headless
    assert launchers({"enable_cameras": True, "device": "cpu"}).enable_cameras
    launcher = launchers(ns, headless=False)  # kwargs win
    assert launcher.headless is False
    assert launchers().device in ("cpu", "cuda:0")


def test_bad_settings_error(launchers):
    with pytest.raises(TypeError, match="headles.*did you mean 'headless'"):
        launchers(headles=True)
    with pytest.raises(ValueError, match="max_app_steps"):
        launchers(max_app_steps=-1, device="cpu")
    with pytest.raises(TypeError, match="Namespace"):
        launchers(["--headless"])
    with pytest.raises(ValueError, match="Allowed: 'cpu'"):
        launchers(device="gpu")


def test_livestream_is_ignored_with_a_note(launchers, capsys):
    launchers(livestream=1, device="cpu")
    assert "livestream" in capsys.readouterr().out


def test_resolve_device(monkeypatch):
    monkeypatch.delenv("SIMLAB_DEVICE", raising=False)
    assert resolve_device("cpu") == "cpu"
    assert resolve_device(None) in ("cpu", "cuda:0")
    monkeypatch.setenv("SIMLAB_DEVICE", "cpu")
    assert resolve_device(None) == "cpu"
    with pytest.raises(ValueError, match="cuda:N"):
        resolve_device("cuda:x")


def test_cuda_without_gpu_is_a_clear_error(monkeypatch):
    import simlab.utils.device as device_rules

    monkeypatch.setattr(device_rules, "gpu_backend_available", lambda: False)
    monkeypatch.delenv("SIMLAB_DEVICE", raising=False)
    assert resolve_device(None) == "cpu"
    with pytest.raises(RuntimeError, match=r"simlab\[gpu\]|no CUDA GPU"):
        resolve_device("cuda")


def test_env_var_device_used_by_launcher(launchers, monkeypatch):
    monkeypatch.setenv("SIMLAB_DEVICE", "cpu")
    assert launchers(make_parser().parse_args([])).device == "cpu"


def test_max_app_steps_bounds_the_loop(launchers):
    app = launchers(max_app_steps=3, device="cpu").app
    steps = 0
    while app.is_running():
        steps += 1
        app.update()
    assert steps == 3
    assert not app.is_running()


def test_max_app_steps_from_the_environment(launchers, monkeypatch):
    """Scripts that make ``AppLauncher(headless=...)`` without the flags (Isaac Lab's frame-transformer
    tutorial) are bounded by $SIMLAB_MAX_APP_STEPS; an explicit value wins; a bad value is named."""
    monkeypatch.setenv("SIMLAB_MAX_APP_STEPS", "2")
    assert launchers(headless=True, device="cpu").max_app_steps == 2
    assert launchers(max_app_steps=5, device="cpu").max_app_steps == 5
    monkeypatch.setenv("SIMLAB_MAX_APP_STEPS", "two")
    with pytest.raises(ValueError, match="SIMLAB_MAX_APP_STEPS must be an int >= 0, got 'two'"):
        launchers(headless=True, device="cpu")


def test_unbounded_app_runs_until_closed(launchers):
    app = launchers(device="cpu").app
    assert all(app.is_running() for _ in range(100))
    app.close()
    assert not app.is_running()
    app.close()  # idempotent


def test_first_sigint_stops_loop_second_raises(launchers):
    previous = signal.getsignal(signal.SIGINT)
    app = launchers(device="cpu").app
    steps = 0
    while app.is_running():
        steps += 1
        if steps == 5:
            signal.raise_signal(signal.SIGINT)  # first Ctrl+C: the loop ends cleanly
    assert steps == 5 and app.interrupted
    with pytest.raises(KeyboardInterrupt):
        signal.raise_signal(signal.SIGINT)  # second Ctrl+C aborts
    app.close()
    assert signal.getsignal(signal.SIGINT) is previous  # handler restored


def test_sigint_without_polling_raises_at_once(launchers):
    launchers(device="cpu")
    with pytest.raises(KeyboardInterrupt):
        signal.raise_signal(signal.SIGINT)


def test_close_restores_handler_even_after_interrupt(launchers):
    previous = signal.getsignal(signal.SIGINT)
    app = launchers(device="cpu").app
    assert signal.getsignal(signal.SIGINT) is not previous
    app.close()
    assert signal.getsignal(signal.SIGINT) is previous


def test_import_is_light():
    import subprocess
    import sys

    code = "import sys, simlab.app; print('torch' in sys.modules, 'mujoco' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "False"]


def test_ranks_are_read_for_distributed_runs(monkeypatch, launchers):
    monkeypatch.setenv("RANK", "3")
    monkeypatch.setenv("LOCAL_RANK", "1")
    launcher = launchers({"distributed": True, "device": "cpu"})
    assert (launcher.local_rank, launcher.global_rank, launcher.device) == (1, 3, "cpu")
    launcher = launchers({"device": "cpu"})  # not distributed: rank 0, as in Isaac Lab
    assert (launcher.local_rank, launcher.global_rank) == (0, 0)
