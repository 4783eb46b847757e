"""The web viewer's camera is the env's viewer camera (``cfg.viewer``) as its videos have it, and moves
with the env or asset it follows. A websocket client stands in for the browser page; the camera is read
where viser keeps it (the client's camera), less the shift mjviser gives the scene (its fixed bodies' frame)."""

from __future__ import annotations

import importlib.util
import threading
import time

import numpy as np
import pytest
import torch
from headless_browser import free_port
from viewer_camera import draw_frame, make_env

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.envs.utils.viewer import view_frame
from simlab.viewer import SimSource

pytestmark = pytest.mark.skipif(
    importlib.util.find_spec("viser") is None or importlib.util.find_spec("mjviser") is None,
    reason="simlab[viewer] (viser, mjviser) is not installed",
)

_CAMERA = {"type": "ViewerCameraMessage", "wxyz": [1.0, 0.0, 0.0, 0.0], "position": [3.0, 3.0, 3.0], "fov": 1.0,
           "near": 0.01, "far": 1000.0, "image_height": 480, "image_width": 640, "look_at": [0.0, 0.0, 0.0],
           "up_direction": [0.0, 0.0, 1.0]}  # fmt: skip


class _Page:
    """viser's page on a websocket: it says where its camera is once (viser then counts it as a
    client and places its camera) and reads whatever the server sends until closed."""

    def __init__(self, viewer):
        import msgspec
        import viser
        from websockets.sync.client import connect

        self._ws = connect(viewer.url.replace("http://", "ws://"), subprotocols=[f"viser-v{viser.__version__}"],
                           max_size=None, open_timeout=30)  # fmt: skip
        self._ws.send(msgspec.msgpack.encode(_CAMERA))
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()
        deadline = time.monotonic() + 30
        while not viewer.server.get_clients() and time.monotonic() < deadline:
            time.sleep(0.01)
        (self.client,) = viewer.server.get_clients().values()
        while np.allclose(self.client.camera.position, _CAMERA["position"]) and time.monotonic() < deadline:
            time.sleep(0.01)  # the viewer places the camera of a page that connects

    def _read(self) -> None:
        try:
            while True:
                self._ws.recv()
        except Exception:  # closed
            return

    def close(self) -> None:
        self._ws.close()


def _camera(viewer, page: _Page) -> tuple[np.ndarray, np.ndarray]:
    """The page's eye and look-at point in the followed env's MuJoCo frame."""
    shift = np.asarray(viewer.scene.fixed_bodies_frame.position)  # where mjviser moved the scene to
    return page.client.camera.position - shift, page.client.camera.look_at - shift


@pytest.fixture
def open_web():
    from simlab.viewer.web import WebViewer

    opened = []

    def open_on(env, follow: int = 0):
        viewer = WebViewer(SimSource.of_env(env), port=free_port(), follow=follow)
        opened.append(viewer)
        page = _Page(viewer)
        opened.append(page)
        draw_frame(viewer)
        return viewer, page

    yield open_on
    for thing in reversed(opened):
        thing.close()


def test_the_web_viewer_looks_from_the_videos_eye_at_their_look_at_point(open_web):
    """The cartpoles' world-frame camera (eye (8, 0, 5), lookat (0, 0, 0)) frames both envs in videos,
    looking at a point between them; it stays there while a cart slides along its rail."""
    env = make_env("simlab/Cartpole-v0")
    try:
        u = env.unwrapped
        video = view_frame(u, u.cfg.viewer)
        viewer, page = open_web(u)
        eye, lookat = _camera(viewer, page)
        np.testing.assert_allclose(lookat, video.lookat, atol=1e-6)
        np.testing.assert_allclose(eye, video.eye, atol=1e-6)
        robot = u.scene["robot"]
        joint_pos = robot.data.joint_pos.clone()
        joint_pos[0, 0] += 1.0  # env 0's cart moves 1 m along its rail
        robot.write_joint_state_to_sim(joint_pos, robot.data.joint_vel.clone())
        u.sim.forward()
        draw_frame(viewer)
        eye, lookat = _camera(viewer, page)
        np.testing.assert_allclose(lookat, video.lookat, atol=1e-6)
        np.testing.assert_allclose(eye, video.eye, atol=1e-6)
    finally:
        env.close()


def test_the_web_viewer_moves_with_the_followed_asset_and_env(open_web):
    eye, lookat = (3.0, 0.0, 3.0), (0.0, 0.0, 1.0)
    env = make_env("simlab/Cartpole-v0", origin_type="asset_root", asset_name="robot", eye=eye, lookat=lookat)
    try:
        u = env.unwrapped
        robot = u.scene["robot"]
        viewer, page = open_web(u, follow=1)
        root = robot.data.root_pos_w[1].numpy() - u.sim.env_origins[1].numpy()  # env 1's MuJoCo frame
        np.testing.assert_allclose(_camera(viewer, page)[1], root + lookat, atol=1e-6)
        np.testing.assert_allclose(_camera(viewer, page)[0], root + eye, atol=1e-6)
        pose = robot.data.root_pose_w.clone()
        pose[1, :3] += torch.tensor([1.0, 0.5, 0.0])  # env 1's robot moves; env 0's stays
        robot.write_root_pose_to_sim(pose)
        u.sim.forward()
        draw_frame(viewer)
        np.testing.assert_allclose(_camera(viewer, page)[1], root + lookat + [1.0, 0.5, 0.0], atol=1e-6)
        viewer.controls.follow = 0  # follow env 0, whose robot stands where env 1's stood
        draw_frame(viewer)
        np.testing.assert_allclose(_camera(viewer, page)[1], root + lookat, atol=1e-6)
    finally:
        env.close()
