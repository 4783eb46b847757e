"""The manager-based camera cartpole configs (Isaac Lab's ``cartpole_camera_env_cfg``) and the
observation space of a non-concatenated group, bounded by its terms' clip ranges.

Oracle for depth: the pinhole model. The camera sits 3 m above the ground, pitched 12 degrees down;
below the cart, a pixel's ray meets the ground plane at 3 / (the ray's downward component).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch
from conftest import rendering_available

from simlab.envs import ManagerBasedRLEnv
from simlab.tasks.manager_based.classic.cartpole.cartpole_camera_env_cfg import (
    CartpoleDepthCameraEnvCfg,
    CartpoleRGBCameraEnvCfg,
)

pytestmark = pytest.mark.skipif(not rendering_available(), reason="no OpenGL context for the cameras")


def make_env(cfg_class, **observation_changes) -> ManagerBasedRLEnv:
    cfg = cfg_class()
    cfg.scene.num_envs = 2
    cfg.sim.device = "cpu"
    for key, value in observation_changes.items():
        setattr(cfg.observations.policy, key, value)
    return ManagerBasedRLEnv(cfg=cfg)


def ground_distance(row: int, col: int, size: int = 100, aperture: float = 20.955, focal: float = 24.0) -> float:
    """Distance from the camera to the ground along the ray through pixel (row, col)."""
    pitch = 2 * math.atan2(0.1045, 0.9945)  # the config's quaternion (w, 0, y, 0): 12 degrees nose down
    up = -(row + 0.5 - size / 2) * aperture / size / focal  # image rows run downwards
    left = -(col + 0.5 - size / 2) * aperture / size / focal
    norm = math.sqrt(1 + up**2 + left**2)
    down = (math.sin(pitch) - up * math.cos(pitch)) / norm  # downward part of the unit ray, world frame
    return 3.0 / down


def test_depth_camera_sees_the_ground_where_the_pinhole_model_says():
    env = make_env(CartpoleDepthCameraEnvCfg)
    try:
        obs, _ = env.reset()
        image = obs["policy"]
        assert image.shape == (2, 100, 100, 1)
        for row, col in ((49, 49), (50, 50), (60, 30), (70, 80)):
            expected = ground_distance(row, col)
            assert float(image[0, row, col, 0]) == pytest.approx(expected, abs=0.02), (row, col)
        assert (image[:, :20] == 0).all()  # sky: nothing within 20 m, written as 0
    finally:
        env.close()


def test_rgb_observation_is_mean_free_and_clip_bounds_its_space():
    env = make_env(CartpoleRGBCameraEnvCfg, concatenate_terms=False)
    try:  # no clip: an unbounded space
        space = env.single_observation_space["policy"]["image"]
        assert np.all(space.low == -np.inf) and np.all(space.high == np.inf) and space.shape == (100, 100, 3)
        obs, _ = env.reset()
        image = obs["policy"]["image"]
        torch.testing.assert_close(image.mean(dim=(1, 2)), torch.zeros(2, 3), atol=1e-5, rtol=0)
        assert image.abs().max() > 0.05  # not a blank frame
    finally:
        env.close()
    cfg = CartpoleRGBCameraEnvCfg()
    cfg.scene.num_envs, cfg.sim.device = 2, "cpu"
    cfg.observations.policy.concatenate_terms = False
    cfg.observations.policy.image.clip = (-0.02, 0.02)
    env = ManagerBasedRLEnv(cfg=cfg)
    try:  # a clipped term: its space is the clip range, and the observations lie in it
        space = env.single_observation_space["policy"]["image"]
        assert np.all(space.low == -0.02) and np.all(space.high == 0.02)
        obs, _ = env.reset()
        image = obs["policy"]["image"]
        assert space.contains(image[0].numpy()) and (image.abs() == 0.02).any()  # the clip was reached
    finally:
        env.close()
