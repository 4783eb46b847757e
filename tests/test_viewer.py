"""Live viewers: the web viewer seen in headless Chromium, the controls, and runs that survive a viewer."""

from __future__ import annotations

import importlib.util
import os
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time

import mujoco
import numpy as np
import pytest
import torch
from headless_browser import CHROMIUM, HeadlessChromium, free_port

from simlab.cli.main import main
from simlab.viewer import SimSource, open_viewer, resolve_viewer_kind
from simlab.viewer.live import LiveViewer

HAVE_VISER = importlib.util.find_spec("viser") is not None and importlib.util.find_spec("mjviser") is not None
needs_browser = pytest.mark.skipif(
    CHROMIUM is None or not HAVE_VISER,
    reason="needs Debian's chromium and simlab[viewer] (scripts/setup.sh dev installs both where apt-get works)",
)
WINDOW = (900, 650)


def _scene(image: np.ndarray) -> np.ndarray:
    """The 3D view: left of viser's control panel, below its notices, above its axes gizmo."""
    return image[170:590, 60:540].astype(int)


def _coloured_pixels(image: np.ndarray) -> int:
    """Pixels of a colour (the cartpoles' navy poles, orange rails): viser's floor and grid are grey."""
    scene = _scene(image)
    return int((scene.max(axis=-1) - scene.min(axis=-1) > 40).sum())


def _floor_drawn(image: np.ndarray) -> bool:
    """viser's grey grid lines show in the 3D view: the page has loaded and drawn a scene."""
    return int((_scene(image).max(axis=-1) < 235).sum()) > 500


def _wait_for_line(proc: subprocess.Popen, text: str, timeout_s: float) -> list[str]:
    """Read the command's output (stderr, or stdout where stderr is merged into it) up to ``text``."""
    stream = proc.stderr if proc.stderr is not None else proc.stdout
    lines: list[str] = []
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        line = stream.readline()
        if not line and proc.poll() is not None:
            break
        lines.append(line)
        if text in line:
            return lines
    raise AssertionError(f"no '{text}' from the command:\n{''.join(lines)}")


class _StillPhysics:
    """State tensors of worlds that never move: an empty scene (the ground only) to compare with."""

    def __init__(self, model: mujoco.MjModel):
        self.model = model

    def data(self, name: str) -> torch.Tensor:
        return torch.zeros(1, getattr(mujoco.MjData(self.model), name).shape[0])


@needs_browser
@pytest.mark.slow  # a `simlab random` run watched through headless Chromium: ~10 s on the idle 2-core machine
def test_web_viewer_shows_the_robots_moving_in_a_browser(tmp_path):
    port = free_port()
    cmd = [sys.executable, "-m", "simlab", "random", "--task", "simlab/Cartpole-v0", "--num_envs", "4",
           "--device", "cpu", "--viewer", "web", "--viewer_port", str(port)]  # fmt: skip
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        line = _wait_for_line(proc, f"Web viewer: http://localhost:{port}/?token=", 120)[-1]
        url = line.split("Web viewer: ", 1)[1].strip()
        with HeadlessChromium(WINDOW) as browser:
            browser.open(url)  # the printed URL, token included: the page and its websocket get in
            # the page loads viser's client, which then receives the scene over its websocket: wait for it
            robots_drawn = lambda image: _coloured_pixels(image) > 200  # noqa: E731
            first = browser.screenshot_when(robots_drawn, 120, str(tmp_path / "first.png"))
            moved_on = lambda image: (np.abs(_scene(first) - _scene(image)).sum(axis=-1) > 60).sum() > 100  # noqa: E731
            second = browser.screenshot_when(moved_on, 60, str(tmp_path / "second.png"))
    finally:
        proc.send_signal(signal.SIGINT)
        proc.wait(timeout=60)

    empty_port = free_port()
    ground = mujoco.MjModel.from_xml_string('<mujoco><worldbody><geom type="plane" size="0 0 1"/></worldbody></mujoco>')
    viewer = open_viewer(SimSource(ground, _StillPhysics(ground), torch.zeros(1, 3), 0.02), "web", empty_port)
    try:
        viewer.after_step()
        with HeadlessChromium(WINDOW) as browser:
            browser.open(viewer.url)
            empty = browser.screenshot_when(_floor_drawn, 120, str(tmp_path / "empty.png"))
    finally:
        viewer.close()

    assert _floor_drawn(empty), "the empty scene's page never drew its floor: nothing to compare the robots with"
    assert _coloured_pixels(first) > max(200, 10 * _coloured_pixels(empty)), "the robots are not drawn"
    moved = (np.abs(_scene(first) - _scene(second)).sum(axis=-1) > 60).sum()
    assert moved > 100, "the picture does not change while the sim runs"


def _ground_source() -> SimSource:
    ground = mujoco.MjModel.from_xml_string('<mujoco><worldbody><geom type="plane" size="0 0 1"/></worldbody></mujoco>')
    return SimSource(ground, _StillPhysics(ground), torch.zeros(1, 3), 0.02)


def _outside_address() -> str | None:
    """This machine's address on its network (not loopback), or None where it has none."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        try:
            probe.connect(("192.0.2.123", 9))  # a UDP "connection" sends nothing: it only picks the route
        except OSError:
            return None
        address = probe.getsockname()[0]
    return None if address.startswith("127.") else address


_CAMERA = {"type": "ViewerCameraMessage", "wxyz": [1.0, 0.0, 0.0, 0.0], "position": [3.0, 3.0, 3.0], "fov": 1.0,
           "near": 0.01, "far": 1000.0, "image_height": 480, "image_width": 640, "look_at": [0.0, 0.0, 0.0],
           "up_direction": [0.0, 0.0, 1.0]}  # fmt: skip


def _viser_session(url: str, cookie: str | None = None, press: tuple = (), seconds: float = 3.0) -> list:
    """Be viser's page on a websocket: say where the camera is, read what the server sends for ``seconds``
    (decoded messages), and press the buttons whose uuids are in ``press`` (or set ``(uuid, value)``)."""
    import msgspec
    import viser
    import zstandard
    from websockets.sync.client import connect

    messages: list[dict] = []
    headers = {"Cookie": cookie} if cookie else None
    with connect(url, subprotocols=[f"viser-v{viser.__version__}"], additional_headers=headers, max_size=None,
                 open_timeout=30) as ws:  # fmt: skip
        ws.send(msgspec.msgpack.encode(_CAMERA))  # viser counts a client from its first camera message
        for item in press:
            uuid, value = item if isinstance(item, tuple) else (item, True)
            ws.send(msgspec.msgpack.encode({"type": "GuiUpdateMessage", "uuid": uuid, "updates": {"value": value}}))
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            try:
                raw = ws.recv(timeout=0.2)
            except TimeoutError:
                continue
            size, packed = int.from_bytes(raw[:8], "little"), int.from_bytes(raw[8:16], "little")
            inner = zstandard.ZstdDecompressor().decompress(raw[16 : 16 + packed], max_output_size=size)
            messages += msgspec.msgpack.decode(inner)["messages"]
    return messages


def _button_uuid(messages: list[dict], label: str) -> str:
    return next(m["uuid"] for m in messages if m["type"] == "GuiButtonMessage" and m["props"]["label"] == label)


@pytest.mark.skipif(not HAVE_VISER, reason="simlab[viewer] (viser, mjviser) is not installed")
def test_the_web_viewer_listens_on_loopback_and_shows_nothing_without_its_token():
    import urllib.error
    import urllib.request

    from websockets.exceptions import InvalidStatus

    port = free_port()
    viewer = open_viewer(_ground_source(), "web", port)
    try:
        assert viewer.server.get_host() == "127.0.0.1" and viewer.port == port
        token = viewer.token
        assert len(token) >= 40 and viewer.url == f"http://localhost:{port}/?token={token}"
        outside = _outside_address()
        if outside is not None:  # from the network: no one listens there
            with pytest.raises(ConnectionRefusedError):
                socket.create_connection((outside, port), timeout=5).close()

        # the page, without its token, with a wrong one, or a wrong cookie: 403 and no viser client
        for url, cookie in ((f"http://127.0.0.1:{port}/", None), (f"http://127.0.0.1:{port}/?token=x{token}", None),
                            (f"http://127.0.0.1:{port}/", f"simlab-viewer-{port}=x{token}")):  # fmt: skip
            request = urllib.request.Request(url, headers={"Cookie": cookie} if cookie else {})
            with pytest.raises(urllib.error.HTTPError) as refused:
                urllib.request.urlopen(request, timeout=30)
            assert refused.value.code == 403 and b"<html" not in refused.value.read().lower()

        # with the token the websocket gets the scene and the buttons, and Pause pauses
        ws = f"ws://127.0.0.1:{port}/"
        seen = _viser_session(f"{ws}?token={token}")
        types = {m["type"] for m in seen}
        assert {"GuiButtonMessage", "GridMessage", "FrameMessage"} <= types, " ".join(sorted(types))  # GUI and scene
        pause, step = _button_uuid(seen, "Pause"), _button_uuid(seen, "Step")
        _viser_session(ws, cookie=f"simlab-viewer-{port}={token}", press=(pause,), seconds=0.5)  # the page's way
        deadline = time.monotonic() + 10
        while not viewer.controls.paused and time.monotonic() < deadline:
            time.sleep(0.05)
        assert viewer.controls.paused, "the Pause button pressed with the token did not pause"

        # the attack: a websocket without the token, or with a wrong one, that knows the buttons' ids
        for url, cookie in ((ws, None), (f"{ws}?token=x{token}", None), (ws, f"simlab-viewer-{port}=x{token}")):
            with pytest.raises(InvalidStatus) as refused:
                _viser_session(url, cookie=cookie, press=(pause, step), seconds=0.5)
            assert refused.value.response.status_code == 403
        time.sleep(1.0)
        assert viewer.controls.paused and viewer.controls.steps_to_run == 0, "a client without the token pressed"
    finally:
        viewer.close()


@pytest.mark.skipif(not HAVE_VISER, reason="simlab[viewer] (viser, mjviser) is not installed")
def test_a_viser_that_starts_its_server_past_the_token_check_is_refused(monkeypatch, capsys):
    """The check sits on the websockets server viser starts; a viser that starts one otherwise would
    serve everyone: the viewer refuses to open instead."""
    import viser

    from simlab.viewer import access

    stopped = []

    class UngatedViser:  # serves without calling websockets.asyncio.server.serve
        def __init__(self, **kwargs):
            pass

        def stop(self):
            stopped.append(True)

    monkeypatch.setattr(viser, "ViserServer", UngatedViser)
    with pytest.raises(access.UngatedServerError, match="without simlab's token check"):
        access.start_gated_viser("127.0.0.1", free_port(), "token")
    assert stopped == [True]
    assert open_viewer(_ground_source(), "web", free_port()) is None
    assert "no web viewer" in capsys.readouterr().err


@pytest.mark.skipif(not HAVE_VISER, reason="simlab[viewer] (viser, mjviser) is not installed")
def test_viewer_host_opens_the_web_viewer_to_the_network_still_behind_its_token():
    import urllib.error
    import urllib.request

    outside = _outside_address()
    if outside is None:
        pytest.skip("this machine has no network address besides loopback")
    port = free_port()
    viewer = open_viewer(_ground_source(), "web", port, host="0.0.0.0")
    try:
        with pytest.raises(urllib.error.HTTPError) as refused:
            urllib.request.urlopen(f"http://{outside}:{port}/", timeout=30)
        assert refused.value.code == 403
        page = urllib.request.urlopen(f"http://{outside}:{port}/?token={viewer.token}", timeout=30)
        assert page.status == 200 and b"<html" in page.read().lower()
        assert viewer.url == f"http://{socket.gethostname()}:{port}/?token={viewer.token}"
    finally:
        viewer.close()


def test_an_unusable_viewer_port_or_headless_with_a_viewer_is_refused(capsys):
    small = ["--task", "simlab/Cartpole-v0", "--num_envs", "2", "--device", "cpu"]
    length = {"random": ["--steps", "1"], "train": ["--max_iterations", "1"], "play": ["--steps", "1"]}
    for command in ("random", "train", "play"):
        for flags, words in ((["--viewer_port", "70000"], ["--viewer_port", "1 to 65535", "70000"]),
                             (["--viewer_port", "0"], ["--viewer_port", "1 to 65535"]),
                             (["--headless", "--viewer", "web"], ["--headless", "--viewer web"]),
                             (["--headless", "--viewer", "native"], ["--headless", "--viewer native"]),
                             (["--viewer_host", ""], ["--viewer_host"])):  # fmt: skip
            argv = [command, *small, *length[command], *flags]
            assert main(argv) == 2, argv
            err = capsys.readouterr().err.strip()
            assert len(err.splitlines()) == 1 and all(word in err for word in words), err
    from simlab.app import AppLauncher

    with pytest.raises(ValueError, match="--headless shows no viewer"):
        AppLauncher(headless=True, viewer="web")
    with pytest.raises(ValueError, match="1 to 65535"):
        AppLauncher(viewer_port=70000)


class _CountingViewer(LiveViewer):
    kind = "counting"

    def __init__(self, source, fail: bool = False):
        super().__init__(source, fps=1000.0)
        self.drawn: list = []
        self._fail_on_draw = fail
        self._start()

    def _draw(self, snapshot) -> None:
        if self._fail_on_draw:
            raise RuntimeError("the browser went away")
        self.drawn.append(snapshot)


@pytest.fixture
def cartpole_source():
    from simlab.envs import ManagerBasedRLEnv
    from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleEnvCfg

    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs = 9
    cfg.sim.device = "cpu"
    env = ManagerBasedRLEnv(cfg)
    env.reset()
    yield env
    env.close()


def test_pause_holds_the_step_loop_and_step_releases_one(cartpole_source):
    viewer = _CountingViewer(SimSource.of_env(cartpole_source))
    viewer.controls.paused = True
    stepper = threading.Thread(target=viewer.after_step)
    stepper.start()
    time.sleep(0.3)
    assert stepper.is_alive(), "a paused viewer lets the step loop run"
    viewer.controls.steps_to_run = 1
    stepper.join(timeout=2.0)
    assert not stepper.is_alive()
    viewer.controls.paused = False
    viewer.controls.follow = 4
    time.sleep(0.01)
    viewer.after_step(torch.ones(9), torch.zeros(9, dtype=torch.bool))
    viewer.close()
    last = viewer.drawn[-1]
    assert last.env_ids[0] == 4 and len(last.env_ids) == 9  # the followed env first, its neighbours after
    origins = cartpole_source.scene.env_origins.numpy()
    np.testing.assert_allclose(last.offsets, origins[last.env_ids] - origins[4], atol=1e-6)
    assert last.states["qpos"].shape == (9, cartpole_source.sim.model.nq)
    assert last.episode_return == pytest.approx(1.0) and last.episode_length == 1


def test_a_failing_viewer_leaves_the_run_going(cartpole_source, capsys):
    viewer = _CountingViewer(SimSource.of_env(cartpole_source), fail=True)
    for _ in range(3):
        viewer.after_step()
        time.sleep(0.05)
    assert viewer.failed
    assert "the browser went away" in capsys.readouterr().err
    # a failed viewer costs the run nothing: no snapshot, no episode bookkeeping
    viewer._snapshot = viewer._track_episodes = lambda *args: pytest.fail("a failed viewer still does work")
    viewer.controls.render_every = 1
    viewer._next_frame = 0.0
    viewer.after_step(torch.ones(9), torch.zeros(9, dtype=torch.bool))
    viewer.close()


@pytest.mark.skipif(not HAVE_VISER, reason="simlab[viewer] (viser, mjviser) is not installed")
def test_viewer_problems_are_warnings_and_the_run_goes_on(tmp_path, capsys, monkeypatch):
    small = ["--task", "simlab/Cartpole-v0", "--num_envs", "2", "--device", "cpu", "--steps", "3"]
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        assert main(["random", *small, "--viewer", "web", "--viewer_port", str(port)]) == 0
    err = capsys.readouterr().err
    assert f"Port {port} is in use" in err and "--viewer_port" in err
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    assert main(["random", *small, "--viewer", "native"]) == 0
    err = capsys.readouterr().err
    assert "needs a display" in err and "--viewer web" in err
    assert resolve_viewer_kind("auto") == "web"  # no display: the browser
    assert resolve_viewer_kind("native", headless=True) == "none"
    with pytest.raises(ValueError, match="allowed: auto, native, web, none"):
        resolve_viewer_kind("window")


@pytest.mark.skipif(not HAVE_VISER, reason="simlab[viewer] (viser, mjviser) is not installed")
def test_render_mode_human_uses_the_apps_viewer():
    import gymnasium as gym

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.app import AppLauncher
    from simlab.tasks.utils import load_cfg_from_registry
    from simlab.viewer.web import WebViewer

    port = free_port()
    launcher = AppLauncher(viewer="web", viewer_port=port)
    assert launcher.viewer == "web" and launcher.viewer_port == port
    for task in ("simlab/Cartpole-v0", "simlab/Cartpole-Direct-v0"):
        cfg = load_cfg_from_registry(task, "env_cfg_entry_point")
        cfg.scene.num_envs, cfg.sim.device = 2, "cpu"
        env = gym.make(task, cfg=cfg, render_mode="human")
        env.reset()
        env.render()
        viewer = env.unwrapped._viewer
        assert isinstance(viewer, WebViewer) and viewer.port == port
        deadline = time.monotonic() + 10
        while viewer.frames_drawn == 0 and time.monotonic() < deadline:
            time.sleep(0.05)
        assert viewer.frames_drawn >= 1
        env.close()
        assert viewer.closed
    launcher.app.close()
    assert AppLauncher(headless=True).viewer == "none"
    with pytest.raises(ValueError, match="viewer_port"):
        AppLauncher(viewer_port=0)


def _read_xwd(path: str) -> np.ndarray:
    """The RGB image of an Xvfb framebuffer file (XWD format, 32 bits per pixel)."""
    import struct

    with open(path, "rb") as f:
        raw = f.read()
    header = struct.unpack(">25I", raw[:100])
    header_size, width, height, bytes_per_line, ncolors = header[0], header[4], header[5], header[12], header[19]
    start = header_size + ncolors * 12
    rows = np.frombuffer(raw[start : start + bytes_per_line * height], dtype=np.uint8).reshape(height, -1)
    return rows[:, : width * 4].reshape(height, width, 4)[..., [2, 1, 0]].astype(int)


def _cartpole_pixels(image: np.ndarray) -> int:
    """Pixels of the cartpoles' orange rails and navy poles (MuJoCo's floor is a grey-blue checker)."""
    r, b = image[..., 0], image[..., 2]
    return int(((r - b > 60) | (b - r > 40)).sum())


@pytest.mark.skipif(shutil.which("Xvfb") is None, reason="needs Debian's xvfb (scripts/setup.sh dev installs it)")
def test_native_viewer_under_xvfb_shows_the_robots_moving(tmp_path):
    display = next(n for n in range(90, 200) if not os.path.exists(f"/tmp/.X{n}-lock"))
    xvfb = subprocess.Popen(["Xvfb", f":{display}", "-screen", "0", "800x600x24", "-fbdir", str(tmp_path)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
    env = dict(os.environ, DISPLAY=f":{display}")
    cmd = [sys.executable, "-m", "simlab", "random", "--task", "simlab/Cartpole-v0", "--num_envs", "9",
           "--device", "cpu", "--viewer", "native"]  # fmt: skip
    run = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    shots: list[np.ndarray] = []
    try:
        _wait_for_line(run, "random actions", 120)
        for _ in range(40):  # software OpenGL draws slowly: wait for two different pictures of the robots
            time.sleep(1.0)
            shot = _read_xwd(str(tmp_path / "Xvfb_screen0"))
            if _cartpole_pixels(shot) > 200:
                shots.append(shot)
            if len(shots) >= 2 and (np.abs(shots[0] - shots[-1]).sum(axis=-1) > 60).sum() > 100:
                break
    finally:
        run.kill()  # the pictures are what is tested here
        run.wait(timeout=60)
        xvfb.terminate()
        xvfb.wait(timeout=30)
    assert len(shots) >= 2, "the window never showed the cartpoles"
    assert (np.abs(shots[0] - shots[-1]).sum(axis=-1) > 60).sum() > 100, "the picture does not change"


@pytest.mark.skipif(not HAVE_VISER, reason="simlab[viewer] (viser, mjviser) is not installed")
def test_the_app_loop_shows_the_simulation(cartpole_source):
    """Tutorial scripts poll ``simulation_app.is_running()``: that is where the app's viewer draws."""
    from simlab.app import AppLauncher
    from simlab.viewer.web import WebViewer

    launcher = AppLauncher(viewer="web", viewer_port=free_port())
    app = launcher.app
    try:
        for _ in range(3):
            assert app.is_running()
            cartpole_source.step(torch.zeros(9, 1))
        assert isinstance(app.viewer, WebViewer) and app.viewer.source.num_envs == 9
    finally:
        app.close()
        AppLauncher(headless=True).app.close()
    assert app.viewer is None
