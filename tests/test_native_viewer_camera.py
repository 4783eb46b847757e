"""The native viewer's camera is the env's viewer camera (``cfg.viewer``) as its videos have it, and
moves with the env or asset it follows, keeping the person's turns and zoom. MuJoCo's window is
replaced by its camera and scene (no display needed); tests/test_viewer.py shows the real window."""

from __future__ import annotations

import contextlib
import math

import mujoco
import mujoco.viewer
import numpy as np
import pytest
import torch
from viewer_camera import draw_frame, make_env

import simlab.tasks  # noqa: F401 - registers the tasks
import simlab.viewer.native as native
from simlab.envs.utils.viewer import view_frame
from simlab.viewer import SimSource


class _Window:
    """MuJoCo's passive viewer window without the window: its free camera and user scene."""

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, **kwargs):
        self.cam = mujoco.MjvCamera()
        self.user_scn = mujoco.MjvScene(model, maxgeom=10000)

    def lock(self):
        return contextlib.nullcontext()

    def is_running(self) -> bool:
        return True

    def set_texts(self, texts) -> None:
        pass

    def sync(self) -> None:
        pass

    def close(self) -> None:
        pass


@pytest.fixture
def open_native(monkeypatch):
    monkeypatch.setattr(native, "display_available", lambda: True)
    monkeypatch.setattr(mujoco.viewer, "launch_passive", _Window)
    opened = []

    def open_on(env, follow: int = 0) -> native.NativeViewer:
        opened.append(native.NativeViewer(SimSource.of_env(env), follow=follow))
        return opened[-1]

    yield open_on
    for viewer in opened:
        viewer.close()


def _eye(cam: mujoco.MjvCamera) -> np.ndarray:
    """Where MuJoCo's free camera stands: ``distance`` back from ``lookat`` along its view direction."""
    az, el = math.radians(cam.azimuth), math.radians(cam.elevation)
    forward = np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
    return np.asarray(cam.lookat) - cam.distance * forward


def test_the_native_viewer_looks_from_the_videos_eye_at_their_look_at_point(open_native):
    """The depth cartpole's camera looks level at its cart 2.5 m up (eye (7, 0, 2.5), lookat (0, 0, 2.5)),
    not from the ground at the floor's edge."""
    env = make_env("simlab/Cartpole-Depth-v0")
    try:
        u = env.unwrapped
        video = view_frame(u, u.cfg.viewer)
        cam = open_native(u)._handle.cam
    finally:
        env.close()
    assert cam.type == mujoco.mjtCamera.mjCAMERA_FREE
    np.testing.assert_allclose(cam.lookat, video.lookat, atol=1e-9)
    np.testing.assert_allclose(_eye(cam), video.eye, atol=1e-9)
    assert cam.lookat[2] > 1.5 and cam.elevation == pytest.approx(0.0) and cam.azimuth == pytest.approx(180.0)


def test_the_native_viewer_moves_with_the_followed_asset_and_env(open_native):
    eye, lookat = (3.0, 0.0, 3.0), (0.0, 0.0, 1.0)
    env = make_env("simlab/Cartpole-v0", origin_type="asset_root", asset_name="robot", eye=eye, lookat=lookat)
    try:
        u = env.unwrapped
        robot = u.scene["robot"]
        viewer = open_native(u, follow=1)
        cam = viewer._handle.cam
        root = robot.data.root_pos_w[1].numpy() - u.sim.env_origins[1].numpy()  # env 1's MuJoCo frame
        np.testing.assert_allclose(cam.lookat, root + lookat, atol=1e-6)
        np.testing.assert_allclose(_eye(cam), root + eye, atol=1e-6)
        cam.azimuth, cam.elevation, cam.distance = 30.0, -20.0, 5.0  # the person turns and zooms
        pose = robot.data.root_pose_w.clone()
        pose[1, :3] += torch.tensor([1.0, 0.5, 0.0])  # env 1's robot moves; env 0's stays
        robot.write_root_pose_to_sim(pose)
        u.sim.forward()
        draw_frame(viewer)
        np.testing.assert_allclose(cam.lookat, root + lookat + [1.0, 0.5, 0.0], atol=1e-6)
        assert (cam.azimuth, cam.elevation, cam.distance) == (30.0, -20.0, 5.0)
        viewer.controls.follow = 0  # `[`: follow env 0, whose robot stands where env 1's stood
        draw_frame(viewer)
        np.testing.assert_allclose(cam.lookat, root + lookat, atol=1e-6)
    finally:
        env.close()
