"""Video frames from MuJoCo Warp's ray tracer (no OpenGL), checked against MuJoCo's OpenGL renderer.

MuJoCo Warp runs here on Warp's CPU device (``SimulationCfg.engine = "mujoco_warp"``); on a GPU the
same code runs on CUDA.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
import torch
from conftest import rendering_available

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.envs.utils.viewer import renderer_kind, view_frame
from simlab.sim.warp_renderer import WarpRenderer, camera_rotation
from simlab.tasks.utils import parse_env_cfg

mjw = pytest.importorskip("mujoco_warp", reason="needs mujoco-warp (pip install 'simlab[gpu]')")

SIZE = (120, 90)


@pytest.fixture(scope="module")
def cartpoles():
    cfg = parse_env_cfg("simlab/Cartpole-v0", device="cpu", num_envs=9)
    cfg.sim.engine = "mujoco_warp"
    cfg.seed = 0
    env = gym.make("simlab/Cartpole-v0", cfg=cfg, render_mode="rgb_array").unwrapped
    env.reset(seed=0)
    yield env
    env.close()


def _changed(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs(a.astype(np.int16) - b.astype(np.int16)).sum(axis=-1) > 30


def _frames(env, renderer) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The scene, the reference env alone, and the scene after the poles moved."""
    frame = view_frame(env, env.cfg.viewer, 9)
    shot = lambda ids, offsets: renderer.render(env.sim.physics, ids, offsets, frame.eye, frame.lookat)  # noqa: E731
    scene, alone = shot(frame.env_ids, frame.offsets), shot(frame.env_ids[:1], frame.offsets[:1])
    qpos = env.sim.physics.data("qpos")
    saved = qpos.clone()
    qpos[:, 1] += 1.0  # every pole tips over by a radian
    moved = shot(frame.env_ids, frame.offsets)
    qpos.copy_(saved)
    return scene, alone, moved


def test_warp_frames_show_the_envs_where_opengl_draws_them(cartpoles):
    renderer = WarpRenderer(cartpoles.sim.spec, cartpoles.sim.physics, *SIZE, max_envs=9)
    scene, alone, moved = _frames(cartpoles, renderer)
    assert scene.shape == (SIZE[1], SIZE[0], 3) and scene.dtype == np.uint8
    assert scene.std() > 5  # not a blank image
    assert _changed(scene, alone).sum() > 50  # the neighbours are drawn into the reference's scene
    warp_moved = _changed(scene, moved)
    assert warp_moved.sum() > 50  # the poles are drawn where the state says
    if not rendering_available():
        pytest.skip("no OpenGL backend here to compare with")
    from simlab.sim.renderer import OffscreenRenderer

    gl_scene, _, gl_moved = _frames(cartpoles, OffscreenRenderer(cartpoles.sim.model, *SIZE, max_envs=9))
    gl_moved = _changed(gl_scene, gl_moved)
    overlap = (warp_moved & gl_moved).sum() / (warp_moved | gl_moved).sum()
    assert overlap > 0.5, f"the poles moved in different places: IoU {overlap:.2f}"


def test_warp_frames_show_the_dome_lights_sky_as_opengl_does(cartpoles):
    """The cartpole's dome light is the sky above the horizon: the ray tracer shades missed rays with
    the model's skybox, in the colours OpenGL draws it."""
    eye, lookat = (-6.0, 0.0, 2.5), (0.0, 0.0, 2.5)  # level: the upper half of the frame is sky
    shot = lambda renderer: renderer.render(cartpoles.sim.physics, [0], np.zeros((1, 3)), eye, lookat)  # noqa: E731
    sky = shot(WarpRenderer(cartpoles.sim.spec, cartpoles.sim.physics, *SIZE, max_envs=1))[:10].astype(int)
    assert sky.min() > 100  # the dome's light grey, not black
    if not rendering_available():
        pytest.skip("no OpenGL backend here to compare with")
    from simlab.sim.renderer import OffscreenRenderer

    gl_sky = shot(OffscreenRenderer(cartpoles.sim.model, *SIZE, max_envs=1))[:10].astype(int)
    assert np.abs(sky - gl_sky).max() <= 4


def test_renderer_choice(monkeypatch, cartpoles):
    monkeypatch.setenv("SIMLAB_RENDERER", "warp")
    assert renderer_kind(uses_mujoco_warp=True) == "warp"
    with pytest.raises(ValueError, match="MuJoCo Warp simulations only"):
        renderer_kind(uses_mujoco_warp=False)
    monkeypatch.setenv("SIMLAB_RENDERER", "vulkan")
    with pytest.raises(ValueError, match="'auto', 'opengl', 'warp'"):
        renderer_kind(uses_mujoco_warp=True)
    monkeypatch.setenv("SIMLAB_RENDERER", "warp")
    cartpoles.cfg.viewer.resolution = SIZE
    image = cartpoles.render()
    assert image.shape == (SIZE[1], SIZE[0], 3) and type(cartpoles._renderer).__name__ == "WarpRenderer"


def test_camera_rotation_looks_at_the_target():
    rotation = camera_rotation([2.0, 6.0, 5.0], [-6.0, 6.0, 0.0])
    np.testing.assert_allclose(rotation.T @ rotation, np.eye(3), atol=1e-12)
    forward = -rotation[:, 2]
    np.testing.assert_allclose(forward, np.array([-8.0, 0.0, -5.0]) / np.sqrt(89.0), atol=1e-12)
    assert rotation[2, 1] > 0  # the image's up points up
    with pytest.raises(ValueError, match="coincide"):
        camera_rotation([1, 1, 1], [1, 1, 1])
    straight_down = camera_rotation([0, 0, 5], [0, 0, 0])
    np.testing.assert_allclose(straight_down.T @ straight_down, np.eye(3), atol=1e-12)
    assert torch.isfinite(torch.as_tensor(straight_down)).all()
