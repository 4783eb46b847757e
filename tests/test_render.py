"""Offscreen rendering of the cartpole: an image that is not blank and follows the pole."""

from __future__ import annotations

import numpy as np
import pytest
import torch

from simlab.envs import ManagerBasedRLEnv
from simlab.sim.renderer import look_at
from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleEnvCfg


def test_look_at_matches_mujoco_free_camera_convention():
    lookat, distance, azimuth, elevation = look_at((8.0, 0.0, 5.0), (0.0, 0.0, 0.0))
    assert distance == pytest.approx(np.hypot(8.0, 5.0))
    assert azimuth == pytest.approx(180.0)  # looking along -x
    assert elevation == pytest.approx(-np.degrees(np.arctan2(5.0, 8.0)))  # looking down
    with pytest.raises(ValueError, match="coincide"):
        look_at((1, 2, 3), (1, 2, 3))


@pytest.fixture
def env():
    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs = 2
    cfg.sim.device = "cpu"
    cfg.viewer.resolution = (160, 120)
    cfg.viewer.eye = (4.0, 0.0, 2.5)
    cfg.viewer.lookat = (0.0, 0.0, 2.0)
    cfg.viewer.origin_type = "env"
    env = ManagerBasedRLEnv(cfg, render_mode="rgb_array")
    env.reset()
    try:
        env.render()
    except RuntimeError as err:  # no OpenGL on this machine
        env.close()
        pytest.skip(f"offscreen rendering unavailable: {err}")
    yield env
    env.close()


def test_render_gives_an_image_that_follows_the_pole(env):
    robot = env.scene["robot"]
    robot.write_joint_state_to_sim(torch.zeros(2, 2), torch.zeros(2, 2))
    env.sim.forward()
    upright = env.render()
    assert upright.shape == (120, 160, 3) and upright.dtype == np.uint8
    assert upright.std() > 5  # not a blank frame
    robot.write_joint_state_to_sim(torch.tensor([[0.0, 1.2], [0.0, 1.2]]), torch.zeros(2, 2))
    env.sim.forward()
    tilted = env.render()
    changed = np.abs(upright.astype(int) - tilted.astype(int)).sum(axis=-1) > 30
    assert changed.mean() > 0.002  # the pole's pixels moved


def test_render_needs_a_render_mode():
    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs = 1
    cfg.sim.device = "cpu"
    env = ManagerBasedRLEnv(cfg)
    with pytest.raises(RuntimeError, match="render_mode='rgb_array'"):
        env.render()
    env.close()
