"""Steering a velocity policy: a user command overrides the sampled command of chosen envs inside the
step (eagerly and in an emulated CUDA graph), and the viewers' keys and controls set it.

The end-to-end checks play the shipped Go2 flat policy: pressing Up in MuJoCo's window (Xvfb,
xdotool) makes the followed robot walk forward; the web page's Steer tab changes the command.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import textwrap
import threading
import time
from types import SimpleNamespace

import gymnasium as gym
import pytest
import torch
from conftest import cuda_available, wait_for
from headless_browser import HeadlessChromium, free_port
from test_graph_contract import _Sim, emulated_cuda_graph  # noqa: F401 (a fixture)
from test_viewer import HAVE_VISER, _viser_session, needs_browser

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.envs.mdp.commands import UniformVelocityCommandCfg
from simlab.envs.utils.cuda_graph import EnvStepper
from simlab.tasks.utils.parse_cfg import parse_env_cfg
from simlab.viewer import open_viewer
from simlab.viewer.steering import VelocitySteering

GO2 = "simlab/Velocity-Flat-Unitree-Go2-v0"
gpu = pytest.mark.skipif(not cuda_available(), reason="needs an NVIDIA GPU and mujoco-warp")
USER = (0.7, -0.3, 0.4)


# -- the command term's user command --------------------------------------------------------------


class CommandToyEnv:
    """An env-shaped object whose step is the velocity command term's update (torch ops only), so the
    emulated graph replays all of it; a robot whose heading turns a little each step."""

    device = "cpu"
    step_dt = 0.02

    def __init__(self, n: int = 4, seed: int = 0):
        torch.manual_seed(seed)
        self.num_envs = n
        self.sim = _Sim()
        self.cfg = SimpleNamespace(sim=SimpleNamespace(use_cuda_graph=True), check_finite_actions=True)
        data = SimpleNamespace(
            heading_w=torch.zeros(n), root_lin_vel_b=torch.zeros(n, 3), root_ang_vel_b=torch.zeros(n, 3)
        )
        self.scene = {"robot": SimpleNamespace(data=data, is_initialized=True)}
        cfg = UniformVelocityCommandCfg(
            asset_name="robot",
            resampling_time_range=(100.0, 100.0),  # nothing is resampled in the test unless released
            heading_command=True,  # each step sets the yaw rate from the heading error
            heading_control_stiffness=0.5,
            rel_heading_envs=1.0,
            ranges=UniformVelocityCommandCfg.Ranges(
                lin_vel_x=(-1.0, 1.0), lin_vel_y=(-1.0, 1.0), ang_vel_z=(-1.0, 1.0), heading=(-0.5, 0.5)
            ),
        )
        self.term = cfg.class_type(cfg, self)
        self.term.enable_user_command()
        self.term.reset()

    def graph_blockers(self) -> list[str]:
        return []

    def _step_body(self, action):
        self.scene["robot"].data.heading_w.add_(action[:, 0])
        self.term.compute(self.step_dt)
        return {"policy": self.term.command.clone()}, torch.zeros(self.num_envs), self.term.time_left.clone()


@pytest.mark.parametrize("graphed", [False, True], ids=["eager", "emulated-graph"])
def test_a_user_command_replaces_the_sampled_one_of_its_env_only_inside_the_step(emulated_cuda_graph, graphed):  # noqa: F811
    env, twin = CommandToyEnv(), CommandToyEnv()  # the twin is never steered: what the others must match
    steppers = []
    for e in (env, twin):
        e.sim.can_capture_steps = graphed
        steppers.append(EnvStepper(e, e._step_body, warmup=2))
    turn = torch.full((4, 1), 0.05)

    def step() -> tuple[torch.Tensor, torch.Tensor]:
        return tuple(stepper(turn)[0]["policy"] for stepper in steppers)

    for _ in range(4):  # past the capture
        mine, theirs = step()
    assert steppers[0].is_graphed == graphed, steppers[0].mode
    torch.testing.assert_close(mine, theirs)

    env.term.set_user_command(USER, [2])  # between steps, as the viewer does
    for _ in range(3):
        mine, theirs = step()
        assert torch.allclose(mine[2], torch.tensor(USER)), mine
        assert not torch.allclose(theirs[2], torch.tensor(USER))
        keep = [0, 1, 3]
        torch.testing.assert_close(mine[keep], theirs[keep])  # the others follow their heading as before
    assert not torch.equal(theirs[:, 2], step()[1][:, 2]), "the heading envs' yaw rate should change per step"

    env.term.release_user_command([2])
    mine, theirs = step()
    assert not torch.allclose(mine[2], torch.tensor(USER)), "released: env 2 draws a new command"
    assert mine[2, :2].abs().max() <= 1.0 and mine[2, 2].abs() <= 1.0
    assert float(env.term.time_left[2]) > 99.0, "a new command comes with a new timer"
    torch.testing.assert_close(mine[[0, 1, 3]], theirs[[0, 1, 3]])


def test_a_user_command_is_refused_in_one_line_where_it_cannot_work():
    env = CommandToyEnv()
    with pytest.raises(ValueError, match=r"a user command has shape \(3,\) \(or \(4, 3\), one per env\), got \(2,\)"):
        env.term.set_user_command([1.0, 2.0], [0])
    fresh = CommandToyEnv()
    fresh.term._user_command = None  # as before enable_user_command()
    with pytest.raises(RuntimeError, match="call enable_user_command"):
        fresh.term.set_user_command(USER, [0])
    fresh._stepper = SimpleNamespace(is_graphed=True)
    fresh.step_is_graphed = True
    with pytest.raises(RuntimeError, match="after the env's step was captured as a CUDA graph"):
        fresh.term.enable_user_command()


@pytest.mark.parametrize(
    "device",
    ["cpu", pytest.param("cuda:0", marks=[pytest.mark.gpu, gpu])],  # on the GPU the step is graphed
)
def test_the_policy_of_the_go2_sees_the_viewers_command_for_the_followed_env_only(device):
    cfg = parse_env_cfg(GO2, device=device, num_envs=4)
    cfg.seed = 0
    env = gym.make(GO2, cfg=cfg).unwrapped
    try:
        steering = VelocitySteering.of_env(env)
        assert steering is not None and steering.name == "base_velocity"
        assert steering.ranges == ((-1.0, 1.0), (-1.0, 1.0), (-1.0, 1.0)) and steering.steps == (0.5, 0.5, 0.5)
        env.reset()
        term = env.command_manager.get_term("base_velocity")
        names = env.observation_manager.active_terms["policy"]
        dims = env.observation_manager.group_obs_term_dim["policy"]
        start = sum(d[0] for d in dims[: names.index("velocity_commands")])
        zero = torch.zeros(4, env.action_manager.total_action_dim, device=device)
        for _ in range(4):  # past the capture of the step, where it is graphed
            env.step(zero)
        assert env.step_is_graphed == device.startswith("cuda"), env.step_mode
        user = torch.tensor([0.5, 0.0, 1.0], device=device)

        steering.nudge(0, 1)  # Up
        steering.nudge(2, 1)  # Left: turn left
        steering.nudge(2, 1)
        steering.nudge(2, 1)  # clipped at the range
        assert steering.wanted == (0.5, 0.0, 1.0)
        steering.sync(1)  # the viewer follows env 1
        before = term.command.clone()
        obs, *_ = env.step(zero)
        seen = obs["policy"][:, start : start + 3]
        assert torch.allclose(seen[1], user), seen
        torch.testing.assert_close(seen[[0, 2, 3], :2], before[[0, 2, 3], :2])  # the others keep theirs

        steering.sync(3)  # the viewer follows env 3: env 1 goes back to the task's commands
        obs, *_ = env.step(zero)
        seen = obs["policy"][:, start : start + 3]
        assert torch.allclose(seen[3], user)
        assert not torch.allclose(seen[1], user)
        steering.stop()
        steering.sync(3)
        obs, *_ = env.step(zero)
        assert torch.equal(obs["policy"][3, start : start + 3], torch.zeros(3, device=device))
    finally:
        env.close()


# -- the native viewer: arrow keys typed into MuJoCo's window (Xvfb, xdotool) ----------------------------

# `simlab play` as the command runs it, with an on_step hook that prints the robots' forward speed
# and commands every 10 steps (0.2 s)
PLAY_REPORTING = textwrap.dedent(
    """
    import json
    import sys
    import simlab.cli.play as play
    from simlab.cli.main import main

    plain = play.rollout

    def rollout(env, policy, steps, on_step=None, **kw):
        def report(base, obs, actions):
            if on_step is not None:
                on_step(base, obs, actions)
            if base.common_step_counter % 10 == 0:
                vx = base.scene["robot"].data.root_lin_vel_b[:, 0].tolist()
                command = base.command_manager.get_command("base_velocity").tolist()
                print("STEER", json.dumps({"vx": vx, "command": command}), flush=True)
        return plain(env, policy, steps, report, **kw)

    play.rollout = rollout
    sys.exit(main(sys.argv[1:]))
    """
)


class ReportingPlay:
    """``simlab play`` of the Go2 flat policy on 2 envs (PLAY_REPORTING) with a viewer, its reports
    collected as they arrive."""

    def __init__(self, tmp_path, viewer_args: list[str], env: dict[str, str], timeout_s: float = 180.0):
        script = tmp_path / "play_reporting.py"
        script.write_text(PLAY_REPORTING)
        cmd = [sys.executable, str(script), "play", "--task", GO2, "--use_pretrained_checkpoint", "--num_envs", "2",
               "--device", "cpu", "--no_export", *viewer_args]  # fmt: skip
        self.run = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.received: list[tuple[float, str]] = []  # (arrival time, line)
        self._reader = threading.Thread(
            target=lambda: self.received.extend((time.monotonic(), line) for line in self.run.stdout)
        )
        self._reader.start()
        self.deadline = time.monotonic() + timeout_s

    def reports(self, since: float = 0.0) -> list[dict]:
        return [json.loads(line.split("STEER", 1)[1]) for t, line in list(self.received)
                if t >= since and line.startswith("STEER")]  # fmt: skip

    def wait_for_line(self, text: str) -> str:
        while not any(text in line for _, line in list(self.received)):
            self.check()
        return next(line for _, line in list(self.received) if text in line)

    def observe(self, settle: float, seconds: float) -> list[dict]:
        """The reports of ``seconds`` from ``settle`` seconds on (at least one)."""
        start = time.monotonic() + settle
        while time.monotonic() < start + seconds or not self.reports(start):
            self.check()
        return self.reports(start)

    def check(self) -> None:
        assert time.monotonic() < self.deadline and self.run.poll() is None, "".join(line for _, line in self.received)
        time.sleep(0.2)

    def stop(self) -> None:
        self.run.kill()
        self.run.wait(timeout=60)
        self._reader.join(timeout=30)


def _mean_vx(reports: list[dict]) -> float:
    return sum(r["vx"][0] for r in reports) / len(reports)


@pytest.mark.slow  # ~30 s on the 2-core machine: play's start-up, software OpenGL, a few seconds of walking
@pytest.mark.skipif(
    shutil.which("Xvfb") is None or shutil.which("xdotool") is None,
    reason="needs Debian's xvfb and xdotool (scripts/setup.sh dev installs them)",
)
def test_the_arrow_keys_in_the_native_viewer_steer_the_go2_policy(tmp_path):
    display = next(n for n in range(90, 200) if not os.path.exists(f"/tmp/.X{n}-lock"))
    xvfb = subprocess.Popen(["Xvfb", f":{display}", "-screen", "0", "1024x768x24"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
    env = dict(os.environ, DISPLAY=f":{display}", PYTHONUNBUFFERED="1")
    env.pop("MUJOCO_GL", None)
    play = ReportingPlay(tmp_path, ["--viewer", "native"], env)
    xdo = dict(os.environ, DISPLAY=f":{display}")

    def press(key: str, settle: float, seconds: float) -> list[dict]:
        subprocess.run(["xdotool", "key", key], env=xdo, timeout=30, check=True)
        return play.observe(settle, seconds)

    try:
        play.observe(0.0, 0.0)  # the window is up and the policy walks
        window = subprocess.run(["xdotool", "search", "--name", "MuJoCo"], env=xdo, capture_output=True,
                                text=True, timeout=30).stdout.split()  # fmt: skip
        assert window, "no MuJoCo window"
        subprocess.run(["xdotool", "windowfocus", window[0]], env=xdo, timeout=30, check=True)
        stopped = press("BackSpace", 2.0, 1.0)
        forward = press("Up", 1.5, 2.0)
        sideways = press("shift+Left", 0.3, 0.2)
        turning = press("Left", 0.3, 0.2)
        released = press("Return", 0.3, 0.2)
    finally:
        play.stop()
        xvfb.terminate()
        xvfb.wait(timeout=30)

    assert all(r["command"][0] == [0.0, 0.0, 0.0] for r in stopped), stopped
    assert abs(_mean_vx(stopped)) < 0.15, stopped  # it stands
    assert all(r["command"][0] == [0.5, 0.0, 0.0] for r in forward), forward
    assert _mean_vx(forward) > 0.3, forward  # Up: the followed robot walks forward
    assert all(r["command"][1] != r["command"][0] for r in stopped + forward)  # env 1 keeps the task's commands
    assert sideways[-1]["command"][0] == [0.5, 0.5, 0.0] and turning[-1]["command"][0] == [0.5, 0.5, 0.5]
    assert released[-1]["command"][0] != [0.5, 0.5, 0.5], "Enter: back to the task's commands"
    print(f"forward speed after Up: {_mean_vx(forward):.2f} m/s (commanded 0.5)")


# -- the web viewer: the Steer tab's controls ----------------------------------------------------------


def _gui_uuid(messages: list[dict], label: str) -> str:
    return next(m["uuid"] for m in messages if m.get("props", {}).get("label") == label)


@pytest.mark.skipif(not HAVE_VISER, reason="simlab[viewer] (viser, mjviser) is not installed")
def test_the_web_viewers_steer_controls_set_the_followed_envs_command():
    cfg = parse_env_cfg(GO2, device="cpu", num_envs=2)
    cfg.seed = 0
    env = gym.make(GO2, cfg=cfg).unwrapped
    port = free_port()
    viewer = open_viewer(env, "web", port, steer=True)
    try:
        assert viewer is not None and viewer.steering is not None
        env.reset()
        command = env.command_manager.get_term("base_velocity").command
        zero = torch.zeros(2, env.action_manager.total_action_dim)
        ws = f"ws://127.0.0.1:{port}/?token={viewer.token}"  # the page's websocket, with the viewer's token
        seen = _viser_session(ws, seconds=1.5)
        forward = _gui_uuid(seen, "Forward (m/s)")

        def step_with(updates: tuple, wanted) -> torch.Tensor:
            _viser_session(ws, press=updates, seconds=0.3)
            wait_for(lambda: viewer.steering.wanted == wanted, 30, f"the viewer to want {wanted}")
            viewer.after_step()  # the step loop hands the command over, between steps
            env.step(zero)
            return command.clone()

        other = command[1].clone()
        after = step_with(((forward, 0.6),), (0.6, 0.0, 0.0))
        torch.testing.assert_close(after[0], torch.tensor([0.6, 0.0, 0.0]))  # the followed env
        assert torch.allclose(after[1, :2], other[:2]), "env 1 keeps the task's command"
        after = step_with((_gui_uuid(seen, "Stop"),), (0.0, 0.0, 0.0))
        assert torch.equal(after[0], torch.zeros(3))
        after = step_with((_gui_uuid(seen, "Task's commands"),), None)
        assert not torch.equal(after[0], torch.zeros(3)), "released: env 0 draws a task command"
        assert "the task's (random)" in viewer.steering.describe()
    finally:
        viewer.close()
        env.close()


@needs_browser
@pytest.mark.slow  # ~30 s on the 2-core machine: play's start-up, a headless browser, a few seconds of walking
def test_the_steer_tab_in_the_browser_steers_the_go2_policy(tmp_path):
    port = free_port()
    play = ReportingPlay(
        tmp_path, ["--viewer", "web", "--viewer_port", str(port)], dict(os.environ, PYTHONUNBUFFERED="1")
    )
    try:
        url = play.wait_for_line(f"Web viewer: http://localhost:{port}/?token=").split("Web viewer: ", 1)[1].strip()
        with HeadlessChromium((1100, 750)) as browser:
            browser.open(url)  # the printed URL, token included

            def click(text: str) -> bool:
                """Click the button or tab labelled ``text``; False while the page does not show it."""
                centre = browser.evaluate(
                    "(() => { const e = [...document.querySelectorAll('button, [role=tab]')].find("
                    f"b => b.textContent.trim() === {json.dumps(text)}); if (!e) return null;"
                    " const r = e.getBoundingClientRect(); return [r.x + r.width / 2, r.y + r.height / 2]; })()"
                )
                for kind in ("mouseMoved", "mousePressed", "mouseReleased") if centre else ():
                    browser.call("Input.dispatchMouseEvent", type=kind, x=centre[0], y=centre[1], button="left",
                                 clickCount=1)  # fmt: skip
                return bool(centre)

            wait_for(lambda: click("Steer") and click("Stop"), 120, "the Steer tab's Stop button")
            stopped = play.observe(2.0, 1.0)
            # the forward slider, focused, then five presses of the right arrow: five of its 0.1 m/s steps
            assert browser.evaluate(
                "(() => { const e = [...document.querySelectorAll('[role=slider]')].find("
                "s => s.getBoundingClientRect().width > 0); e.focus(); return document.activeElement === e; })()"
            )
            for _ in range(5):
                for kind in ("keyDown", "keyUp"):
                    browser.call("Input.dispatchKeyEvent", type=kind, key="ArrowRight", code="ArrowRight",
                                 windowsVirtualKeyCode=39)  # fmt: skip
            forward = play.observe(1.5, 2.0)
            browser.screenshot(str(tmp_path / "steer_tab.png"))
    finally:
        play.stop()

    assert all(r["command"][0] == [0.0, 0.0, 0.0] for r in stopped), stopped
    assert abs(_mean_vx(stopped)) < 0.15, stopped
    assert all(r["command"][0] == pytest.approx([0.5, 0.0, 0.0]) for r in forward), forward
    assert _mean_vx(forward) > 0.3, forward
    assert all(r["command"][1] != r["command"][0] for r in stopped + forward)
    print(f"forward speed after the slider: {_mean_vx(forward):.2f} m/s (commanded 0.5)")
