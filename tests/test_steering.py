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
from test_graph_contract import _Sim, emulated_cuda_graph  # noqa: F401 (a fixture)

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.envs.mdp.commands import UniformVelocityCommandCfg
from simlab.envs.utils.cuda_graph import EnvStepper
from simlab.tasks.utils.parse_cfg import parse_env_cfg
from simlab.viewer.steering import VelocitySteering

GO2 = "simlab/Velocity-Flat-Unitree-Go2-v0"
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


def test_the_policy_of_the_go2_sees_the_viewers_command_for_the_followed_env_only():
    cfg = parse_env_cfg(GO2, device="cpu", num_envs=4)
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
        zero = torch.zeros(4, env.action_manager.total_action_dim)

        steering.nudge(0, 1)  # Up
        steering.nudge(2, 1)  # Left: turn left
        steering.nudge(2, 1)
        steering.nudge(2, 1)  # clipped at the range
        assert steering.wanted == (0.5, 0.0, 1.0)
        steering.sync(1)  # the viewer follows env 1
        before = term.command.clone()
        obs, *_ = env.step(zero)
        seen = obs["policy"][:, start : start + 3]
        assert torch.allclose(seen[1], torch.tensor([0.5, 0.0, 1.0])), seen
        torch.testing.assert_close(seen[[0, 2, 3], :2], before[[0, 2, 3], :2])  # the others keep theirs

        steering.sync(3)  # the viewer follows env 3: env 1 goes back to the task's commands
        obs, *_ = env.step(zero)
        seen = obs["policy"][:, start : start + 3]
        assert torch.allclose(seen[3], torch.tensor([0.5, 0.0, 1.0]))
        assert not torch.allclose(seen[1], torch.tensor([0.5, 0.0, 1.0]))
        steering.stop()
        steering.sync(3)
        obs, *_ = env.step(zero)
        assert torch.equal(obs["policy"][3, start : start + 3], torch.zeros(3))
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


def _reports(lines: list[tuple[float, str]], since: float) -> list[dict]:
    return [json.loads(line.split("STEER", 1)[1]) for t, line in list(lines) if t >= since and line.startswith("STEER")]


@pytest.mark.slow  # ~30 s on the 2-core machine: play's start-up, software OpenGL, a few seconds of walking
@pytest.mark.skipif(
    shutil.which("Xvfb") is None or shutil.which("xdotool") is None,
    reason="needs Debian's xvfb and xdotool (scripts/setup.sh dev installs them)",
)
def test_the_arrow_keys_in_the_native_viewer_steer_the_go2_policy(tmp_path):
    script = tmp_path / "play_reporting.py"
    script.write_text(PLAY_REPORTING)
    display = next(n for n in range(90, 200) if not os.path.exists(f"/tmp/.X{n}-lock"))
    xvfb = subprocess.Popen(["Xvfb", f":{display}", "-screen", "0", "1024x768x24"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
    env = dict(os.environ, DISPLAY=f":{display}", PYTHONUNBUFFERED="1")
    env.pop("MUJOCO_GL", None)
    cmd = [sys.executable, str(script), "play", "--task", GO2, "--use_pretrained_checkpoint", "--num_envs", "2",
           "--device", "cpu", "--viewer", "native", "--no_export"]  # fmt: skip
    run = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    xdo = dict(os.environ, DISPLAY=f":{display}")
    received: list[tuple[float, str]] = []
    reader = threading.Thread(target=lambda: received.extend((time.monotonic(), line) for line in run.stdout))
    reader.start()
    deadline = time.monotonic() + 180

    def press(key: str, settle: float, observe: float) -> list[dict]:
        """Type ``key``, let the robot settle, then the reports of ``observe`` seconds."""
        subprocess.run(["xdotool", "key", key], env=xdo, timeout=30, check=True)
        start = time.monotonic() + settle
        while time.monotonic() < start + observe or not _reports(received, start):
            assert time.monotonic() < deadline and run.poll() is None, "".join(line for _, line in received)
            time.sleep(0.2)
        return _reports(received, start)

    try:
        while not _reports(received, 0.0):  # the window is up and the policy walks
            assert time.monotonic() < deadline and run.poll() is None, "".join(line for _, line in received)
            time.sleep(0.2)
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
        run.kill()
        run.wait(timeout=60)
        reader.join(timeout=30)
        xvfb.terminate()
        xvfb.wait(timeout=30)

    assert all(r["command"][0] == [0.0, 0.0, 0.0] for r in stopped), stopped
    assert abs(sum(r["vx"][0] for r in stopped) / len(stopped)) < 0.15, stopped  # it stands
    assert all(r["command"][0] == [0.5, 0.0, 0.0] for r in forward), forward
    walked = sum(r["vx"][0] for r in forward) / len(forward)
    assert walked > 0.3, forward  # Up: the followed robot walks forward
    assert all(r["command"][1] != r["command"][0] for r in stopped + forward)  # env 1 keeps the task's commands
    assert sideways[-1]["command"][0] == [0.5, 0.5, 0.0] and turning[-1]["command"][0] == [0.5, 0.5, 0.5]
    assert released[-1]["command"][0] != [0.5, 0.5, 0.5], "Enter: back to the task's commands"
    print(f"forward speed after Up: {walked:.2f} m/s (commanded 0.5)")
